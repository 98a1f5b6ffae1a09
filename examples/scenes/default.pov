// hfray's default scene: Rocky Mountain National Park (Colorado) from a
// real elevation model, coloured by its palette the way the 1996 thesis
// coloured its mountains, lit by a low sun with shadows.
// Data: ../data/rmnp_co_152x187.gif (index = height; see ../data/README.md).
// The field is 152 x 187 samples of ~233 m; the relief (2281-4261 m) is
// about 1/18 of the width, shown here twice as high.
#version 3.7;
global_settings { assumed_gamma 1.0 }

camera {
  location <0.5, 0.55, -0.55>
  look_at  <0.5, 0.02, 0.55>
  right x*image_width/image_height
  angle 55
}

light_source { <-3, 4, -1.5> color rgb <1.0, 0.96, 0.88> }

background { color rgb <0.55, 0.7, 0.9> }

height_field {
  gif "../data/rmnp_co_152x187.gif"
  image_map
  smooth
  scale <1, 0.11, 1.23>
  finish { ambient 0.25 diffuse 0.8 }
}
