#declare R = 0.5;
#declare V = <1, 2, 3> * 2 - (x + y) / 4;
camera { orthographic location <0, 5, -5> look_at 0 up y*2 right x*2*image_width/image_height sky y }
light_source { <5, 5, -5>, rgb 1 }
light_source { V color red 1 green 0.5 blue 0.25 }
sphere { <0, 1, 0>, R pigment { color rgbt <1, 0, 0, 0.5> } finish { phong 0.8 phong_size 40 specular 0.2 roughness 0.05 } }
box { <-1, -1, -1>, <1, 1, 1> rotate <10, 20, 30> scale <1, 2, 3> translate -x }
cylinder { 0, y, 0.25 open texture { pigment { rgbf <0, 1, 0, 0.3> } finish { ambient 0.2 } } }
cone { 0, 1, y*2, 0 matrix <1,0,0, 0,1,0, 0,0,1, 0,0,0> }
triangle { <0,0,0>, <1,0,0>, <0,1,0> transform { scale 2 translate z } }
plane { <0, 1, 0>, -1 pigment { color gray 0.5 } normal { bumps 0.3 } }
height_field { pot "h.pot" hierarchy off water_level = 0.5 smooth }
global_settings { max_trace_level 10 ambient_light rgb <0.1, 0.1, 0.1> }
background { rgb <0.2, 0.3, 0.4> }
