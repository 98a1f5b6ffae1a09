// The default view (Rocky Mountain National Park, 152 x 187 samples of a
// real elevation model, examples/data/README.md) coloured by height with a
// gradient colour map, so POV-Ray 3.7 renders the same file (it does not
// take the thesis's `image_map` palette colouring inside a height_field):
// the real-DEM scene of the README's POV-Ray comparison.
//   cargo run --release --example render -- examples/scenes/rmnp_gradient.pov \
//       -o rmnp.tga --stats
//   povray +Irmnp_gradient.pov +W320 +H200 -A +WT1 -D
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
  smooth
  // In the field's unit cube, before its scale: 0 = lowest, 1 = highest.
  pigment {
    gradient y
    color_map {
      [0.0 color rgb <0.25, 0.45, 0.2>]
      [0.5 color rgb <0.55, 0.5, 0.35>]
      [0.8 color rgb <0.6, 0.58, 0.55>]
      [1.0 color rgb <0.95, 0.95, 0.97>]
    }
  }
  finish { ambient 0.25 diffuse 0.8 }
  scale <1, 0.11, 1.23>
}
