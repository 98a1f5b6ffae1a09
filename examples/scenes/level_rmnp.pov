// The level view of issue 13: the camera at terrain height looking
// horizontally across a real DEM (Rocky Mountain National Park, 152 x 187
// samples, examples/data/README.md), one light with shadows, meant for
// 640 x 400 without anti-aliasing:
//   cargo run --release --example render -- examples/scenes/level_rmnp.pov \
//       -o level.tga --width 640 --height 400 --stats
//   povray +Ilevel_rmnp.pov +W640 +H400 -A +WT1 -D
// `up` is the world's vertical and the view is horizontal, so each image
// column's rays share their horizontal direction: `render` traces TGA
// output bottom-up and resumes each ray where the ray below stopped
// (`--coherence on`, the default; `resumed=` in --stats).
#version 3.7;
global_settings { assumed_gamma 1.0 }

camera {
  location <0.45, 0.075, 0.12>
  look_at  <0.6, 0.075, 1.2>
  right x*image_width/image_height
  angle 65
}

light_source { <-2, 3, -1> color rgb <1.0, 0.96, 0.88> }

background { color rgb <0.55, 0.7, 0.9> }

height_field {
  gif "../data/rmnp_co_152x187.gif"
  smooth
  pigment { color rgb <0.55, 0.5, 0.4> }
  scale <1, 0.11, 1.23>
  finish { ambient 0.25 diffuse 0.8 }
}
