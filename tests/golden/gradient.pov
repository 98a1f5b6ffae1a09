// Colour by height, compared with POV-Ray 3.7's own render of this file
// (tests/render_gradient.rs; gradient_povray.md says how the reference
// image was made). island16.pgm and island8.pgm are written by the test.
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <1.05, 1.25, -1.3> look_at <1.05, 0.1, 0.55> right x*4/3 angle 58 }
light_source { <-2, 4, -3> color rgb <1, 1, 1> }
background { color rgb <0.5, 0.7, 0.9> }

// 16-bit island; the pigment comes before the scale, so it is scaled with
// the field: the map's 0..1 spans the field's full height.
height_field { pgm "island16.pgm" smooth
  pigment { gradient y
    color_map {
      [0.0 color rgb <0.10, 0.35, 0.12>]
      [0.45 color rgb <0.55, 0.45, 0.30>]
      [0.8 color rgb <0.85, 0.85, 0.85>]
      [1.0 color rgb <1, 1, 1>]
    }
  }
  scale <1, 0.4, 1>
}

// 8-bit island beside it; the pigment comes after the transforms, so they
// do not move it: its own scale 0.1 makes bands 0.1 world units apart.
height_field { pgm "island8.pgm"
  scale <1, 0.4, 1> translate <1.1, 0, 0>
  pigment { gradient y
    colour_map { [0 rgb <0.2, 0.2, 0.6>] [0.5, rgb <0.9, 0.6, 0.2>] [1 rgb <0.2, 0.2, 0.6>] }
    scale 0.1
  }
}

// A plane striped along x, repeating every half unit (just below the
// fields' flat ground, so no surface is coplanar with another).
plane { y, -0.02
  pigment { gradient x color_map { [0 color rgb 1] [0.5 color rgb 0.3] [1 color rgb 1] } scale 0.5 }
}

// A sphere with a diagonal gradient, moved with the sphere.
sphere { <0, 0, 0>, 0.22
  pigment { gradient <1, 1, 0>
    color_map { [0 color rgb <1, 0, 0>] [0.5 color rgb <0, 0, 1>] [1 color rgb <1, 0, 0>] }
    scale 0.3
  }
  translate <1.05, 0.55, 1.35>
}
