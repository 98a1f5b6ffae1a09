#include "colors.inc"
sphere { 0, 1 pigment { color Red*0.5 + Blue } }
