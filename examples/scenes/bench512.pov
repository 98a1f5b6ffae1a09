// The benchmark scene of SPEC.md: a 512 x 512 fractal height field, one
// colour, one light with shadows, 320 x 200 (render without anti-aliasing).
// bench512.pgm is written by `cargo run --release --example bench` (a
// deterministic value-noise fBm, examples/bench_common/mod.rs) next to a
// copy of this file under target/bench512/, where POV-Ray is run as
//   povray +Ibench512.pov +W320 +H200 -A +WT1 -D +FN +Obench512-pov.png
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera {
  location <0.5, 0.8, -0.6>
  look_at  <0.5, 0.1, 0.5>
  right x*image_width/image_height
  angle 60
}
light_source { <-3, 4, -2> color rgb 1 }
background { color rgb <0.5, 0.7, 0.9> }
height_field {
  pgm "bench512.pgm"
  scale <1, 0.3, 1>
  pigment { color rgb <0.6, 0.5, 0.4> }
}
