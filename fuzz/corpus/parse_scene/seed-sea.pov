#version 3.7;
#include "colors.inc"
global_settings { assumed_gamma 1.0 }
#declare Sea = rgb <0.1, 0.3, 0.5>;
camera {
  location <0.5, 0.6, -1.2>
  look_at  <0.5, 0.2, 0.5>
  right x*image_width/image_height
  angle 50
}
light_source { <-10, 20, -15> color White }
background { color SkyBlue }
plane { y, 0.05 pigment { Sea } finish { reflection 0.6 } }
height_field {
  gif "mountain.gif"
  smooth
  water_level 0.05
  pigment { color rgb <0.6, 0.5, 0.4> }
  finish { ambient 0.15 diffuse 0.8 }
  scale <1, 0.5, 1>
}
