//! Error tests: one per error class, asserting the message and `line:col`;
//! and a fuzz test that the parser never panics.

use hfray::scene::{parse_scene, Diagnostic, ParseOptions, Severity, MAX_DECLARATIONS};

fn err_with(src: &str, opts: &ParseOptions) -> String {
    match parse_scene::<8, 4, 4>(src, opts, &mut |_| {}) {
        Ok(_) => panic!("expected an error for {src:?}"),
        Err(e) => {
            assert_eq!(e.severity, Severity::Error);
            e.to_string()
        }
    }
}

fn err(src: &str) -> String {
    err_with(src, &ParseOptions::new(320, 240))
}

// --- lexical ---------------------------------------------------------------

#[test]
fn unterminated_string() {
    assert_eq!(
        err("height_field {\n  gif \"canyon.gif\n}"),
        "2:7: unterminated string: expected a closing `\"` before the end of the line"
    );
}

#[test]
fn unterminated_comment() {
    assert_eq!(
        err("sphere { 0, 1 }\n  /* open /* nested */ never closed"),
        "2:3: unterminated comment: expected `*/` before end of file"
    );
}

#[test]
fn number_literal_out_of_range() {
    assert_eq!(
        err("sphere { 0, 1e999 }"),
        "1:13: number `1e999` is out of range"
    );
}

#[test]
fn stray_character() {
    assert_eq!(
        err("sphere { 0, 1 } @"),
        "1:17: expected a scene item (camera, light_source, an object or a directive), found character '@'"
    );
}

// --- structure -------------------------------------------------------------

#[test]
fn unterminated_brace_points_at_the_opening_brace() {
    assert_eq!(
        err("camera { location <0, 0, -5> look_at 0 }\nsphere { 0, 1\n  pigment { rgb 1 }\n"),
        "2:8: unterminated `sphere` block: expected `}` before end of file"
    );
    assert_eq!(
        err("sphere { 0, 1 pigment { rgb 1 "),
        "1:23: unterminated `pigment` block: expected `}` before end of file"
    );
    assert_eq!(
        err("sphere { 0, 1 normal { bumps { { } }"),
        "1:22: unterminated `normal` block: expected `}` before end of file"
    );
}

#[test]
fn missing_open_brace() {
    assert_eq!(err("sphere 0, 1 }"), "1:8: expected `{`, found number 0");
}

#[test]
fn missing_argument_says_what_was_expected() {
    assert_eq!(
        err("sphere { <0, 0, 0> }"),
        "1:20: expected the sphere radius (a float), found `}`"
    );
    assert_eq!(
        err("light_source { <0, 0, 0> }"),
        "1:26: expected the light colour (e.g. `color rgb <1, 1, 1>`), found `}`"
    );
}

#[test]
fn unknown_top_level_item() {
    assert_eq!(
        err("\n  union { sphere { 0, 1 } }"),
        "2:3: unknown top-level item `union`: expected camera, light_source, background, \
         global_settings, height_field, plane, sphere, box, cylinder, cone, triangle or a directive"
    );
}

#[test]
fn unknown_identifier_in_expression() {
    assert_eq!(
        err("sphere { <0, 0, 0>, Radius }"),
        "1:21: unknown identifier `Radius`: expected the sphere radius (a float)"
    );
}

#[test]
fn unknown_object_modifier_is_an_error_not_a_warning() {
    assert_eq!(
        err("sphere { 0, 1 scael 2 }"),
        "1:15: unknown identifier `scael`: expected an object modifier (scale, rotate, translate, \
         matrix, transform, pigment, finish, texture, color) or `}`"
    );
}

#[test]
fn unknown_finish_item() {
    assert_eq!(
        err("sphere { 0, 1 finish { phong 1 shiny 2 } }"),
        "1:32: unknown identifier `shiny`: expected a finish item (ambient, diffuse, phong, \
         phong_size, specular, roughness, reflection) or `}`"
    );
}

#[test]
fn colour_name_without_colors_inc() {
    assert_eq!(
        err("sphere { 0, 1 pigment { color White } }"),
        "1:31: unknown identifier `White`: it is a colors.inc colour; add #include \"colors.inc\" first"
    );
}

// --- values ----------------------------------------------------------------

#[test]
fn wrong_vector_arity() {
    assert_eq!(
        err("sphere { 0, 1 translate <1, 2> }"),
        "1:25: expected a translation (3-vector), found a 2-component vector"
    );
    assert_eq!(
        err("sphere { <1, 2, 3>, <1, 2, 3> }"),
        "1:21: expected the sphere radius (a float), found a 3-component vector"
    );
    assert_eq!(
        err("sphere { 0, 1 pigment { rgb <1, 0, 0, 1> } }"),
        "1:29: expected an rgb vector (3 components), found a 4-component vector"
    );
    assert_eq!(
        err("#include \"colors.inc\"\nsphere { Red, 1 }"),
        "2:10: expected the sphere centre (3-vector), found a colour (5 components)"
    );
}

#[test]
fn vector_literal_length() {
    assert_eq!(
        err("sphere { <1, 2, 3, 4, 5, 6>, 1 }"),
        "1:26: expected a vector of 2 to 5 components, found 6 components"
    );
    assert_eq!(
        err("sphere { <1>, 1 }"),
        "1:10: expected a vector of 2 to 5 components, found 1 component"
    );
    assert_eq!(
        err("sphere { <1, 2 3>, 1 }"),
        "1:16: expected `,` or `>` in the vector, found number 3"
    );
}

#[test]
fn division_by_zero() {
    assert_eq!(
        err("#declare N = 0;\nsphere { 0, 1 translate <1, 2 / N, 3> }"),
        "2:31: division by zero"
    );
    assert_eq!(
        err("sphere { 0, 1 scale <1, 1, 1> / <1, 0, 1> }"),
        "1:31: division by zero"
    );
}

#[test]
fn overflow_is_not_finite() {
    assert_eq!(
        err("#declare Big = 1e200;\nsphere { 0, Big * Big }"),
        "2:17: expression result is not a finite number"
    );
    assert_eq!(
        err("sphere { 0, 1e300 }"),
        "1:13: value must be within the f32 range (about ±3.4e38), found 1e300"
    );
}

#[test]
fn scale_must_be_positive() {
    assert_eq!(
        err("sphere { 0, 1 scale <1, -1, 1> }"),
        "1:21: expected positive scale factors, found <1, -1, 1>"
    );
    assert_eq!(
        err("sphere { 0, 1\n scale 0 }"),
        "2:8: expected positive scale factors, found <0, 0, 0>"
    );
}

#[test]
fn water_level_outside_unit_interval() {
    assert_eq!(
        err("HEIGHT_FIELD { GIF \"a.gif\" WATER_LEVEL = 1.5 }"),
        "1:42: water_level must be in [0, 1], found 1.5"
    );
    assert_eq!(
        err("height_field { gif \"a.gif\" water_level -0.1 }"),
        "1:40: water_level must be in [0, 1], found -0.1"
    );
}

#[test]
fn camera_angle_outside_open_interval() {
    for (a, col) in [("0", 38), ("180", 38), ("-10", 38)] {
        let src = format!("camera {{ location -z look_at 0 angle {a} }}");
        let value: f64 = a.parse().unwrap();
        assert_eq!(
            err(&src),
            format!("1:{col}: camera angle must be in (0, 180) degrees, found {value}")
        );
    }
}

#[test]
fn radius_must_be_positive() {
    assert_eq!(
        err("sphere { 0, 0 }"),
        "1:13: sphere radius must be greater than 0, found 0"
    );
    assert_eq!(
        err("cylinder { 0, y, -1 }"),
        "1:18: cylinder radius must be greater than 0, found -1"
    );
    assert_eq!(
        err("cone { 0, -1, y, 1 }"),
        "1:11: cone radius must be at least 0, found -1"
    );
    assert_eq!(
        err("cone { 0, 0, y, 0 }"),
        "1:8: degenerate cone: both radii are 0"
    );
}

#[test]
fn degenerate_shapes() {
    assert_eq!(
        err("cylinder { <1, 2, 3>, <1, 2, 3>, 1 }"),
        "1:12: degenerate cylinder: base and cap are the same point"
    );
    assert_eq!(
        err("plane { <0, 0, 0>, 1 }"),
        "1:9: degenerate plane: the normal is <0, 0, 0>"
    );
    assert_eq!(
        err("sphere { 0, 1 matrix <1,0,0, 0,0,0, 0,0,1, 0,0,0> }"),
        "1:22: expected an invertible matrix, found a singular or non-finite one"
    );
}

#[test]
fn degenerate_triangle_is_an_error_in_strict_mode() {
    let strict = ParseOptions {
        strict: true,
        ..ParseOptions::new(320, 240)
    };
    assert_eq!(
        err_with("\ntriangle { 0, x, 2*x }", &strict),
        "2:1: degenerate triangle (zero area) (strict mode: not dropped)"
    );
}

#[test]
fn other_ranges() {
    assert_eq!(
        err("global_settings { max_trace_level 0 }"),
        "1:35: max_trace_level must be in [1, 256], found 0"
    );
    assert_eq!(
        err("global_settings { assumed_gamma -1 }"),
        "1:33: assumed_gamma must be greater than 0, found -1"
    );
    assert_eq!(
        err("sphere { 0, 1 finish { roughness 0 } }"),
        "1:34: roughness must be greater than 0, found 0"
    );
}

// --- cameras ----------------------------------------------------------------

#[test]
fn camera_location_equals_look_at() {
    assert_eq!(
        err("camera {\n  location <1, 2, 3>\n  look_at <1, 2, 3>\n}"),
        "3:3: degenerate camera: expected look_at different from location, found both at <1, 2, 3>"
    );
}

#[test]
fn camera_look_direction_parallel_to_sky() {
    assert_eq!(
        err("camera { location <0, 10, 0> look_at <0, 0, 0> }"),
        "1:30: degenerate camera: viewing direction <0, -10, 0> is parallel to sky <0, 1, 0>; \
         expected a sky vector not parallel to it"
    );
    // Checked at the end of the block: a later `sky` fixes it.
    parse_scene::<1, 1, 4>(
        "camera { location <0, 10, 0> look_at 0 sky z }",
        &ParseOptions::new(320, 240),
        &mut |_| {},
    )
    .unwrap();
}

#[test]
fn camera_zero_vector() {
    assert_eq!(
        err("camera { location -z look_at 0 right 0 }"),
        "1:32: degenerate camera: expected a non-zero `right` vector, found <0, 0, 0>"
    );
}

#[test]
fn camera_transforms_and_types_are_not_supported() {
    assert_eq!(
        err("camera { location -z look_at 0 rotate y*30 }"),
        "1:32: `rotate` is not supported: camera transforms are not implemented; place the camera \
         with location and look_at"
    );
    assert_eq!(
        err("camera { fisheye angle 180 }"),
        "1:10: `fisheye` is not supported: only perspective and orthographic cameras are implemented"
    );
}

// --- height fields -------------------------------------------------------------

#[test]
fn height_field_missing_file_name() {
    assert_eq!(
        err("height_field {\n  gif\n  scale 2\n}"),
        "3:3: expected a quoted file name, found `scale`"
    );
    assert_eq!(
        err("height_field { }"),
        "1:16: expected an image format (gif, png, pgm, ppm, tga, pot) and a quoted file name, found `}`"
    );
    assert_eq!(
        err("height_field { png \"\" }"),
        "1:20: expected a file name, found an empty string"
    );
}

#[test]
fn height_field_unsupported_format() {
    assert_eq!(
        err("height_field { jpeg \"a.jpg\" }"),
        "1:16: unsupported height_field format `jpeg`: expected gif, png, pgm, ppm, tga or pot"
    );
    assert_eq!(
        err("height_field { \"terrain.jpg\" }"),
        "1:16: cannot tell the image format of \"terrain.jpg\" from its extension: expected gif, \
         png, pgm, ppm, tga or pot before the file name"
    );
}

#[test]
fn modifiers_on_the_wrong_object() {
    assert_eq!(
        err("sphere { 0, 1 smooth }"),
        "1:15: `smooth` does not apply to sphere"
    );
    assert_eq!(
        err("sphere { 0, 1 water_level 0.5 }"),
        "1:15: `water_level` does not apply to sphere"
    );
    assert_eq!(
        err("box { 0, 1 image_map }"),
        "1:12: `image_map` does not apply to box"
    );
    assert_eq!(
        err("cylinder { 0, y, 1 scale 2 open }"),
        "1:28: misplaced `open`: `open` must directly follow the radius, as in POV-Ray"
    );
    assert_eq!(
        err("clipped_by"),
        "1:1: unknown top-level item `clipped_by`: expected camera, light_source, background, \
         global_settings, height_field, plane, sphere, box, cylinder, cone, triangle or a directive"
    );
    assert_eq!(
        err("sphere { 0, 1 clipped_by { plane { y, 0 } } }"),
        "1:15: `clipped_by` is not supported: clipping changes the geometry and is not implemented"
    );
}

// --- directives --------------------------------------------------------------

#[test]
fn include_other_than_colors_inc() {
    assert_eq!(
        err("#include \"colors.inc\"\n#include \"textures.inc\""),
        "2:10: cannot include \"textures.inc\": only \"colors.inc\" is built in"
    );
    assert_eq!(
        err("#include colors"),
        "1:10: expected a quoted file name, found `colors`"
    );
}

#[test]
fn unsupported_directive() {
    assert_eq!(
        err("#if (1)\n#end"),
        "1:2: unsupported directive `#if`: expected #declare, #local, #include or #version"
    );
}

#[test]
fn declaration_errors() {
    assert_eq!(
        err("#declare x = 1;"),
        "1:10: expected a new identifier, found keyword `x`"
    );
    assert_eq!(
        err("#declare Ball = sphere { 0, 1 }"),
        "1:17: expected a float, vector or colour after `=`, found `sphere` (only float, vector \
         and colour declarations are supported)"
    );
    assert_eq!(
        err("#declare A = 1\nsphere { 0, A }"),
        "2:1: expected `;` after the declared value, found `sphere`"
    );
    assert_eq!(err("#declare A 1;"), "1:12: expected `=`, found number 1");
}

// --- capacities and depth ---------------------------------------------------------

#[test]
fn too_many_objects() {
    let e = parse_scene::<2, 1, 4>(
        "sphere { 0, 1 }\nsphere { 0, 1 }\nsphere { 0, 1 }",
        &ParseOptions::new(320, 240),
        &mut |_| {},
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "3:1: too many objects (capacity 2)");
}

#[test]
fn too_many_lights() {
    let e = parse_scene::<2, 1, 4>(
        "light_source { 0 color 1 }\nlight_source { 0 color 1 }",
        &ParseOptions::new(320, 240),
        &mut |_| {},
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "2:1: too many lights (capacity 1)");
}

#[test]
fn too_many_declarations() {
    let mut src = String::new();
    for i in 0..=MAX_DECLARATIONS {
        src.push_str(&format!("#declare V{i} = {i};\n"));
    }
    assert_eq!(
        err(&src),
        format!(
            "{}:10: too many #declare names (capacity {MAX_DECLARATIONS})",
            MAX_DECLARATIONS + 1
        )
    );
}

#[test]
fn deep_nesting_is_reported_not_a_stack_overflow() {
    let deep_parens = format!(
        "sphere {{ 0, {}1{} }}",
        "(".repeat(100_000),
        ")".repeat(100_000)
    );
    assert_eq!(
        err(&deep_parens),
        "1:77: nesting too deep (limit 64 levels)"
    );
    let deep_vectors = format!("sphere {{ {}1 }}", "<".repeat(100_000));
    assert_eq!(
        err(&deep_vectors),
        "1:74: nesting too deep (limit 64 levels)"
    );
    let deep_braces = format!("sphere {{ 0, 1 normal {} }}", "{".repeat(100_000));
    assert_eq!(
        err(&deep_braces),
        "1:86: nesting too deep (limit 64 levels)"
    );
    let deep_transforms = format!("sphere {{ 0, 1 {} }}", "transform { ".repeat(10_000));
    assert_eq!(
        err(&deep_transforms),
        "1:783: nesting too deep (limit 64 levels)"
    );
    // Many unary minus signs are a loop, not recursion.
    let minus = format!("sphere {{ 0, {}1 }}", "- ".repeat(100_000));
    assert!(parse_scene::<1, 1, 4>(&minus, &ParseOptions::new(320, 240), &mut |_| {}).is_ok());
}

// --- never panic --------------------------------------------------------------------

const FUZZ_SOUP: usize = 3000;
const FUZZ_MUTATIONS: usize = 4000;

struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

const CORPUS: &[&str] = &[
    r#"#version 3.7;
#include "colors.inc"
#declare S = 2; #declare C = rgb <1, 0.5, 0>; #declare V = <1, 2, 3>;
global_settings { assumed_gamma 1 max_trace_level 5 ambient_light White }
camera { perspective location <0.5, 2, -3> look_at <0.5, 0, 0.5> angle 45 right x*image_width/image_height up y sky y direction z }
light_source { <-10, 12, -30> color rgb <1, 0.8, 0.8> translate V }
background { color SkyBlue }
height_field { gif "canyon.gif" smooth water_level 0.01 scale <1, 2, 1> rotate <-20, 25, 0>
  pigment { color C filter 0.1 } finish { ambient 0.2 diffuse 0.7 phong 1 phong_size 40 specular 0.1 roughness 0.05 reflection 0.3 } }
plane { y, 0 pigment { Blue } normal { bumps 0.5 } }
sphere { <0, 1, 0>, S / 2 texture { pigment { rgbft <1, 1, 1, 0.1, 0.2> } } }
box { <0, 0, 0>, <1, 1, 1> matrix <1,0,0, 0,1,0, 0,0,1, 0,0,0> }
cylinder { 0, y, 0.5 open transform { scale 2 translate -x } }
cone { 0, 1, y*2, 0 open }
triangle { 0, x, z }
"#,
    r#"CAMERA { LOCATION <-18, 7.5, -28> LOOK_AT <0.5, 1.07, 0.5> }
LIGHT_SOURCE { <-10, 12, -30> COLOR RGB <1.0, 0.8, 0.8> }
HEIGHT_FIELD { GIF "CANYON.GIF" SCALE <1.0, 2.0, 1.0> ROTATE <-20, 25, 0> TRANSLATE <0, 0, 0>
    COLOR RGB <1.0, 0.8, 0.8> IMAGE_MAP WATER_LEVEL = 0.01 }
/* c /* n */ */ // x
"#,
];

const FRAGMENTS: &[&str] = &[
    "{",
    "}",
    "<",
    ">",
    "(",
    ")",
    ",",
    ";",
    "=",
    "+",
    "-",
    "*",
    "/",
    "#",
    "\"",
    "/*",
    "*/",
    "//",
    "\n",
    " ",
    "0",
    "1",
    ".5",
    "1e-3",
    "1e999",
    "-0",
    "x",
    "y",
    "z",
    "pi",
    "camera",
    "sphere",
    "height_field",
    "gif",
    "\"f.gif\"",
    "pigment",
    "finish",
    "color",
    "rgb",
    "rgbft",
    "scale",
    "rotate",
    "translate",
    "matrix",
    "transform",
    "normal",
    "water_level",
    "open",
    "#declare",
    "#include",
    "\"colors.inc\"",
    "Red",
    "White",
    "image_map",
    "look_at",
    "location",
    "sky",
    "angle",
    "é",
    "\u{0}",
    "\u{FFFF}",
    "🦀",
    "\\",
    "@",
    "[",
    "texture",
    "reflection",
];

#[test]
fn parser_never_panics_on_random_and_mutated_inputs() {
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let opts = [
        ParseOptions::new(320, 240),
        ParseOptions {
            strict: true,
            image_width: 0,
            image_height: 0,
            clock: f32::MAX,
        },
    ];
    let mut errors = 0usize;
    let mut oks = 0usize;
    let mut run = |src: &str, i: usize| {
        let mut warn_count = 0usize;
        let r = parse_scene::<8, 4, 4>(src, &opts[i % 2], &mut |d: &Diagnostic| {
            // Displaying must not panic either.
            let _ = d.to_string();
            warn_count += 1;
        });
        match r {
            Ok(_) => oks += 1,
            Err(e) => {
                let s = e.to_string();
                assert!(e.line >= 1 && e.col >= 1, "{s}");
                errors += 1;
            }
        }
    };
    let mut i = 0usize;
    // Token soup.
    for _ in 0..FUZZ_SOUP {
        let n = rng.below(60);
        let mut s = String::new();
        for _ in 0..n {
            s.push_str(FRAGMENTS[rng.below(FRAGMENTS.len())]);
            if rng.below(3) == 0 {
                s.push(' ');
            }
        }
        run(&s, i);
        i += 1;
    }
    // Mutations of valid scenes: delete, duplicate, replace or insert spans.
    for _ in 0..FUZZ_MUTATIONS {
        let base = CORPUS[rng.below(CORPUS.len())];
        let mut chars: Vec<char> = base.chars().collect();
        for _ in 0..1 + rng.below(4) {
            let len = chars.len().max(1);
            let at = rng.below(len).min(chars.len());
            match rng.below(4) {
                0 => {
                    let end = (at + rng.below(20)).min(chars.len());
                    chars.drain(at..end);
                }
                1 => {
                    let end = (at + rng.below(40)).min(chars.len());
                    let dup: Vec<char> = chars[at..end].to_vec();
                    chars.splice(at..at, dup);
                }
                2 => {
                    if at < chars.len() {
                        chars[at] = FRAGMENTS[rng.below(FRAGMENTS.len())]
                            .chars()
                            .next()
                            .unwrap_or('x');
                    }
                }
                _ => {
                    let frag: Vec<char> = FRAGMENTS[rng.below(FRAGMENTS.len())].chars().collect();
                    chars.splice(at..at, frag);
                }
            }
        }
        let s: String = chars.into_iter().collect();
        run(&s, i);
        i += 1;
    }
    // Every prefix of a valid scene (unterminated everything).
    for base in CORPUS {
        for (k, _) in base.char_indices() {
            run(&base[..k], i);
            i += 1;
        }
    }
    eprintln!("fuzz: {i} inputs, {oks} parsed, {errors} errors");
    // Both outcomes happen, so the inputs exercise more than the lexer.
    assert!(oks > 50, "oks = {oks}");
    assert!(errors > 1000, "errors = {errors}");
}

#[test]
fn composed_transform_overflowing_f32() {
    assert_eq!(
        err("sphere { 0, 1 scale 1e30 scale 1e30 }"),
        "1:26: expected a transform within the f32 range, found one that overflows it"
    );
}
