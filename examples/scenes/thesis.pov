// The thesis's ingredients in one scene: a DEM (Maunga Whau, Auckland),
// a water level that floods the low ground, a reflective sea plane, and a
// light with shadows. Renders the same geometry in POV-Ray 3.7:
//   povray +Ithesis.pov +Othesis_pov.png +W320 +H200 -A File_Gamma=1.0
#version 3.7;
global_settings { assumed_gamma 1.0 }

camera {
  location <-0.35, 0.75, -0.9>
  look_at  <0.5, 0.05, 0.45>
  right x*image_width/image_height
  angle 50
}

light_source { <-2, 3, -1> color rgb <1, 0.95, 0.9> }
background { color rgb <0.5, 0.65, 0.85> }

height_field {
  gif "../data/maunga_whau_volcano_87x61.gif"
  water_level 0.25
  scale <1, 0.3, 0.7>
  pigment { color rgb <0.45, 0.6, 0.3> }
  finish { ambient 0.15 diffuse 0.75 }
}

plane {
  y, 0.07
  pigment { color rgb <0.1, 0.25, 0.4> }
  finish { ambient 0.1 diffuse 0.4 reflection 0.5 }
}
