//! Parse tests: every construct of the scene subset maps to the expected
//! model values.

use hfray::glam::{DVec3, Vec3};
use hfray::scene::colors::{named_color, COLORS};
use hfray::scene::lexer::{Lexer, TokenKind};
use hfray::scene::{
    parse_scene, CameraDesc, Diagnostic, Finish, HeightFieldSource, ImageFormat, Object,
    ParseOptions, Pigment, Projection, Scene, Severity, Shape,
};

/// Each parsed height field's index, format and file name.
fn named<'a>(scene: &S<'a>) -> Vec<(usize, ImageFormat, &'a str)> {
    scene
        .height_field_sources()
        .map(|(i, source)| (i, source.format, source.path))
        .collect()
}
use hfray::Transform;

type S<'a> = Scene<'a, 16, 4>;

fn parse_opts<'a>(src: &'a str, opts: &ParseOptions) -> (S<'a>, Vec<String>) {
    let mut warnings = Vec::new();
    let scene = parse_scene::<16, 4, 4>(src, opts, &mut |d: &Diagnostic| {
        assert_eq!(d.severity, Severity::Warning);
        warnings.push(d.to_string())
    })
    .unwrap_or_else(|e| panic!("{e}"));
    (scene, warnings)
}

fn parse(src: &str) -> S<'_> {
    let (scene, warnings) = parse_opts(src, &ParseOptions::new(320, 240));
    assert!(warnings.is_empty(), "unexpected warnings: {warnings:?}");
    scene
}

fn only_object<'a>(scene: &S<'a>) -> Object<'a> {
    assert_eq!(scene.objects.len(), 1);
    scene.objects[0]
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-6
}

fn t_scale(x: f64, y: f64, z: f64) -> Transform {
    Transform::scale(DVec3::new(x, y, z)).unwrap()
}
fn t_rotate(x: f64, y: f64, z: f64) -> Transform {
    Transform::rotate_degrees(DVec3::new(x, y, z)).unwrap()
}
fn t_translate(x: f64, y: f64, z: f64) -> Transform {
    Transform::translate(DVec3::new(x, y, z)).unwrap()
}

/// The three blocks of the thesis's §5.4, exactly as printed (without the
/// numbered call-outs, which are annotations in the text).
const THESIS_5_4: &str = r#"
CAMERA {
    LOCATION <-18, 7.5, -28>
    LOOK_AT <0.5, 1.07, 0.5>
}

LIGHT_SOURCE { <-10, 12, -30>
    COLOR RGB <1.0, 0.8, 0.8>
}

HEIGHT_FIELD {
    GIF "CANYON.GIF"
    SCALE <1.0, 2.0, 1.0>
    ROTATE <-20, 25, 0>
    TRANSLATE <0, 0, 0>
    COLOR RGB <1.0, 0.8, 0.8>
    IMAGE_MAP
    WATER_LEVEL = 0.01
}
"#;

#[test]
fn thesis_section_5_4_blocks_verbatim() {
    let scene = parse(THESIS_5_4);
    assert_eq!(
        scene.camera,
        CameraDesc {
            location: Vec3::new(-18.0, 7.5, -28.0),
            look_at: Vec3::new(0.5, 1.07, 0.5),
            ..CameraDesc::default()
        }
    );
    assert_eq!(scene.lights.len(), 1);
    assert_eq!(scene.lights[0].position, Vec3::new(-10.0, 12.0, -30.0));
    assert_eq!(scene.lights[0].color, Vec3::new(1.0, 0.8, 0.8));
    let hf = only_object(&scene);
    assert_eq!(
        hf.shape,
        Shape::HeightField {
            field_index: 0,
            smooth: false,
            source: Some(HeightFieldSource {
                format: ImageFormat::Gif,
                path: "CANYON.GIF",
                water_level: 0.01,
                palette_colors: true,
                transform: t_scale(1.0, 2.0, 1.0)
                    .then(&t_rotate(-20.0, 25.0, 0.0))
                    .then(&t_translate(0.0, 0.0, 0.0)),
            }),
        }
    );
    assert_eq!(hf.pigment.color, Vec3::new(1.0, 0.8, 0.8));
    assert_eq!(hf.pigment.filter, 0.0);
    assert_eq!(hf.finish, Finish::default());
    // The placement is the field's, stated once: in its source.
    assert_eq!(hf.transform, Transform::IDENTITY);
    assert_eq!(named(&scene), vec![(0, ImageFormat::Gif, "CANYON.GIF")]);
}

#[test]
fn pov_ray_spelling_of_the_thesis_height_field() {
    let scene = parse(
        r#"height_field { gif "canyon.gif" smooth water_level 0.01
              scale <1, 2, 1> rotate <-20, 25, 0> pigment { color rgb <1, 0.8, 0.8> } }"#,
    );
    match only_object(&scene).shape {
        Shape::HeightField {
            smooth,
            source: Some(source),
            ..
        } => {
            assert!(smooth);
            assert_eq!(source.water_level, 0.01);
            assert!(!source.palette_colors);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn height_field_formats_and_extension_inference() {
    for (src, format, path) in [
        (r#"height_field { gif "a.gif" }"#, ImageFormat::Gif, "a.gif"),
        (r#"height_field { png "b.png" }"#, ImageFormat::Png, "b.png"),
        (r#"height_field { pgm "c.pgm" }"#, ImageFormat::Pgm, "c.pgm"),
        (r#"height_field { ppm "d.ppm" }"#, ImageFormat::Ppm, "d.ppm"),
        (r#"height_field { tga "e.tga" }"#, ImageFormat::Tga, "e.tga"),
        (r#"height_field { pot "f.pot" }"#, ImageFormat::Pot, "f.pot"),
        (
            r#"height_field { "dir/g.PNG" }"#,
            ImageFormat::Png,
            "dir/g.PNG",
        ),
        (r#"height_field { "h.tga" }"#, ImageFormat::Tga, "h.tga"),
        // The format keyword wins over the extension.
        (r#"height_field { gif "x.dat" }"#, ImageFormat::Gif, "x.dat"),
    ] {
        let scene = parse(src);
        assert_eq!(named(&scene), vec![(0, format, path)], "{src}");
    }
}

#[test]
fn height_field_indices_follow_file_order() {
    let scene = parse(
        r#"height_field { gif "a.gif" }
           sphere { 0, 1 }
           height_field { pgm "b.pgm" water_level 0.5 }
           plane { y, 0 }
           height_field { png "c.png" hierarchy off }"#,
    );
    assert_eq!(
        named(&scene),
        vec![
            (0, ImageFormat::Gif, "a.gif"),
            (1, ImageFormat::Pgm, "b.pgm"),
            (2, ImageFormat::Png, "c.png")
        ]
    );
    assert_eq!(scene.objects.len(), 5);
}

#[test]
fn camera_records_every_item() {
    let opts = ParseOptions::new(640, 480);
    let (scene, w) = parse_opts(
        "camera { perspective location <1, 2, -3> look_at <0, 1, 0> angle 45
                  right x*image_width/image_height up y direction <0, 0, 2> sky <0, 1, 0.1> }",
        &opts,
    );
    assert!(w.is_empty());
    let c = scene.camera;
    assert_eq!(c.projection, Projection::Perspective);
    assert_eq!(c.location, Vec3::new(1.0, 2.0, -3.0));
    assert_eq!(c.look_at, Vec3::new(0.0, 1.0, 0.0));
    assert_eq!(c.angle, Some(45.0));
    assert!(close(c.right, Vec3::new(640.0 / 480.0, 0.0, 0.0)));
    assert_eq!(c.up, Vec3::Y);
    assert_eq!(c.direction, Vec3::new(0.0, 0.0, 2.0));
    assert_eq!(c.sky, Vec3::new(0.0, 1.0, 0.1));
}

#[test]
fn camera_orthographic_and_default_right() {
    let scene = parse("camera { orthographic location <0, 10, 0> look_at 0 sky z }");
    let c = scene.camera;
    assert_eq!(c.projection, Projection::Orthographic);
    assert_eq!(c.look_at, Vec3::ZERO);
    assert_eq!(c.sky, Vec3::Z);
    assert_eq!(c.right, Vec3::new(1.33, 0.0, 0.0));
    assert_eq!(c.angle, None);
}

#[test]
fn camera_without_look_at_looks_along_direction() {
    let scene = parse("camera { location <0, 0, 2> direction <0, 0, 1.5> }");
    assert_eq!(scene.camera.look_at, Vec3::new(0.0, 0.0, 3.5));
}

#[test]
fn camera_block_order_does_not_matter_and_last_camera_wins() {
    let a = parse("camera { look_at <1, 0, 0> angle 30 location <0, 0, -4> }").camera;
    let b = parse(
        "camera { location 9 look_at 0 } camera { location <0, 0, -4> angle 30 look_at <1, 0, 0> }",
    )
    .camera;
    assert_eq!(a, b);
}

#[test]
fn no_camera_block_gives_the_default_camera() {
    assert_eq!(parse("sphere { 0, 1 }").camera, CameraDesc::default());
}

#[test]
fn light_source_colour_forms() {
    let scene = parse(
        r#"#include "colors.inc"
           light_source { <1, 2, 3> color rgb <0.5, 0.6, 0.7> }
           light_source { <0, 0, 0>, colour rgb 1 }
           light_source { <0, 0, 0> rgb <0.1, 0.2, 0.3> }
           light_source { <0, 0, 0> color White translate <1, 0, 0> rotate <0, 0, 90> }"#,
    );
    assert_eq!(scene.lights.len(), 4);
    assert_eq!(scene.lights[0].position, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(scene.lights[0].color, Vec3::new(0.5, 0.6, 0.7));
    assert_eq!(scene.lights[1].color, Vec3::ONE);
    assert_eq!(scene.lights[2].color, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(scene.lights[3].color, Vec3::ONE);
    // translate x then rotate 90° about z: +x goes to +y.
    assert!(close(scene.lights[3].position, Vec3::Y));
}

#[test]
fn background_global_settings_and_version() {
    let scene = parse(
        "#version 3.7;
         global_settings { assumed_gamma 1.0 max_trace_level 10 ambient_light rgb <0.5, 0.5, 1> }
         background { color rgb <0.1, 0.2, 0.3> }",
    );
    assert_eq!(scene.version, Some(3.7));
    assert_eq!(scene.settings.assumed_gamma, Some(1.0));
    assert_eq!(scene.settings.max_trace_level, 10);
    assert_eq!(scene.settings.ambient_light, Vec3::new(0.5, 0.5, 1.0));
    assert_eq!(scene.background, Vec3::new(0.1, 0.2, 0.3));
}

#[test]
fn defaults_match_pov_ray() {
    let scene = parse("sphere { 0, 1 }");
    assert_eq!(scene.background, Vec3::ZERO);
    assert_eq!(scene.settings.max_trace_level, 5);
    assert_eq!(scene.version, None);
    let o = only_object(&scene);
    // POV-Ray 3.7's default pigment is black (checked with povray 3.7.0.10).
    assert_eq!(o.pigment, Pigment::default());
    assert_eq!(o.pigment.color, Vec3::ZERO);
    assert_eq!(o.finish, Finish::default());
    assert_eq!(o.transform, Transform::IDENTITY);
}

#[test]
fn every_primitive_parses() {
    let scene = parse(
        "plane { <0, 2, 0>, 1 }
         sphere { <1, 2, 3>, 0.5 }
         box { <1, 1, 1>, <-1, 0, 2> }
         cylinder { <0, 0, 0>, <0, 1, 0>, 0.25 open }
         cylinder { <0, 0, 0> <0, 2, 0> 1 }
         cone { <0, 0, 0>, 1, <0, 1, 0>, 0 open }
         triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> }",
    );
    let shapes: Vec<Shape> = scene.objects.iter().map(|o| o.shape).collect();
    assert_eq!(
        shapes,
        vec![
            // POV-Ray normalises the normal and keeps the distance
            // (trace() against plane { <0,2,0>, 1 } hits y = 1).
            Shape::Plane {
                normal: Vec3::Y,
                distance: 1.0
            },
            Shape::Sphere {
                center: Vec3::new(1.0, 2.0, 3.0),
                radius: 0.5
            },
            Shape::Box {
                min: Vec3::new(-1.0, 0.0, 1.0),
                max: Vec3::new(1.0, 1.0, 2.0)
            },
            Shape::Cylinder {
                base: Vec3::ZERO,
                cap: Vec3::Y,
                radius: 0.25,
                open: true
            },
            Shape::Cylinder {
                base: Vec3::ZERO,
                cap: Vec3::new(0.0, 2.0, 0.0),
                radius: 1.0,
                open: false
            },
            Shape::Cone {
                base: Vec3::ZERO,
                base_radius: 1.0,
                cap: Vec3::Y,
                cap_radius: 0.0,
                open: true
            },
            Shape::Triangle {
                vertices: [Vec3::ZERO, Vec3::X, Vec3::Y]
            },
        ]
    );
}

#[test]
fn keywords_are_case_insensitive() {
    let a = parse("SPHERE { <1, 2, 3>, 1 PIGMENT { COLOR RGB <1, 0, 0> } SCALE 2 }");
    let b = parse("Sphere { <1, 2, 3>, 1 Pigment { Color Rgb <1, 0, 0> } Scale 2 }");
    let c = parse("sphere { <1, 2, 3>, 1 pigment { color rgb <1, 0, 0> } scale 2 }");
    assert_eq!(a.objects[0], c.objects[0]);
    assert_eq!(b.objects[0], c.objects[0]);
}

#[test]
fn transforms_compose_in_written_order() {
    let scene = parse(
        "sphere { 0, 1 scale 2 translate <1, 0, 0> }
         sphere { 0, 1 translate <1, 0, 0> scale 2 }
         sphere { 0, 1 scale <1, 2, 3> rotate <90, 0, 0> translate y }
         sphere { 0, 1 rotate <0, 0, 90> pigment { rgb 1 } translate <0, 0, 5> }",
    );
    let p = |i: usize, v: DVec3| scene.objects[i].transform.to_world().transform_point3(v);
    assert_eq!(p(0, DVec3::ONE), DVec3::new(3.0, 2.0, 2.0));
    assert_eq!(p(1, DVec3::ONE), DVec3::new(4.0, 2.0, 2.0));
    assert_eq!(
        scene.objects[2].transform,
        t_scale(1.0, 2.0, 3.0)
            .then(&t_rotate(90.0, 0.0, 0.0))
            .then(&t_translate(0.0, 1.0, 0.0))
    );
    // Transforms after a pigment still move the object.
    assert!((p(3, DVec3::X) - DVec3::new(0.0, 1.0, 5.0)).length() < 1e-12);
}

#[test]
fn matrix_and_transform_block() {
    let scene = parse(
        "sphere { 0, 1 matrix <1, 0, 0,  0, 2, 0,  0, 0, 3,  4, 5, 6> }
         sphere { 0, 1 transform { scale 2 transform { translate x } } rotate <0, 90, 0> }",
    );
    let m = scene.objects[0]
        .transform
        .to_world()
        .transform_point3(DVec3::ONE);
    assert_eq!(m, DVec3::new(5.0, 7.0, 9.0));
    assert_eq!(
        scene.objects[1].transform,
        t_scale(2.0, 2.0, 2.0)
            .then(&t_translate(1.0, 0.0, 0.0))
            .then(&t_rotate(0.0, 90.0, 0.0))
    );
}

#[test]
fn pigment_colour_forms() {
    let scene = parse(
        r#"#include "colors.inc"
           sphere { 0, 1 pigment { color rgb <1, 0.5, 0.25> } }
           sphere { 0, 1 pigment { colour rgbf <1, 0, 0, 0.5> } }
           sphere { 0, 1 pigment { rgbt <0, 1, 0, 0.25> } }
           sphere { 0, 1 pigment { rgbft <0, 0, 1, 0.1, 0.2> } }
           sphere { 0, 1 pigment { Red } }
           sphere { 0, 1 pigment { color Clear } }
           sphere { 0, 1 pigment { color red 1 green 0.5 filter 0.3 } }
           sphere { 0, 1 pigment { color 0.5 } }
           sphere { 0, 1 pigment { color White * 0.5 transmit 0.75 } }
           sphere { 0, 1 pigment { rgb 1 scale 3 rotate 10*y } }
           sphere { 0, 1 pigment { color gray 0.4 } }
           sphere { 0, 1 pigment { MediumSlateBlue } }"#,
    );
    let p: Vec<(Vec3, f32, f32)> = scene
        .objects
        .iter()
        .map(|o| (o.pigment.color, o.pigment.filter, o.pigment.transmit))
        .collect();
    assert_eq!(
        p,
        vec![
            (Vec3::new(1.0, 0.5, 0.25), 0.0, 0.0),
            (Vec3::new(1.0, 0.0, 0.0), 0.5, 0.0),
            (Vec3::new(0.0, 1.0, 0.0), 0.0, 0.25),
            (Vec3::new(0.0, 0.0, 1.0), 0.1, 0.2),
            (Vec3::new(1.0, 0.0, 0.0), 0.0, 0.0),
            (Vec3::ONE, 1.0, 0.0),
            (Vec3::new(1.0, 0.5, 0.0), 0.3, 0.0),
            // POV-Ray: a bare float fills all five channels.
            (Vec3::splat(0.5), 0.5, 0.5),
            (Vec3::splat(0.5), 0.0, 0.75),
            (Vec3::ONE, 0.0, 0.0),
            (Vec3::splat(0.4), 0.0, 0.0),
            (Vec3::new(0.498039, 0.0, 1.0), 0.0, 0.0),
        ]
    );
}

#[test]
fn finish_items() {
    let scene = parse(
        "sphere { 0, 1 finish { ambient 0.2 diffuse 0.7 phong 0.5 phong_size 60
                                specular 0.3 roughness 0.01 reflection 0.25 } }
         sphere { 0, 1 finish { ambient rgb <0.1, 0.2, 0.3> reflection rgb <0, 0.5, 1> } }
         sphere { 0, 1 finish { reflection { 0.4 } } finish { diffuse 0.9 } }",
    );
    let f0 = scene.objects[0].finish;
    assert_eq!(
        f0,
        Finish {
            ambient: Vec3::splat(0.2),
            diffuse: 0.7,
            phong: 0.5,
            phong_size: 60.0,
            specular: 0.3,
            roughness: 0.01,
            reflection: Vec3::splat(0.25),
        }
    );
    let f1 = scene.objects[1].finish;
    assert_eq!(f1.ambient, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(f1.reflection, Vec3::new(0.0, 0.5, 1.0));
    assert_eq!(f1.diffuse, 0.6);
    // A second finish block modifies the first.
    let f2 = scene.objects[2].finish;
    assert_eq!(f2.reflection, Vec3::splat(0.4));
    assert_eq!(f2.diffuse, 0.9);
}

#[test]
fn texture_block_holds_pigment_and_finish() {
    let scene =
        parse("sphere { 0, 1 texture { pigment { rgb <0, 1, 0> } finish { phong 1 } scale 2 } }");
    let o = only_object(&scene);
    assert_eq!(o.pigment.color, Vec3::Y);
    assert_eq!(o.finish.phong, 1.0);
    // Texture transforms do not move the object.
    assert_eq!(o.transform, Transform::IDENTITY);
}

#[test]
fn expressions_follow_pov_ray_precedence_and_promotion() {
    let opts = ParseOptions {
        image_width: 800,
        image_height: 600,
        clock: 0.25,
        strict: false,
    };
    let (scene, _) = parse_opts(
        "sphere { <1 + 2 * 3, -(1 - 4) / 2, -2 * -3>, 2 * pi / pi }
         sphere { 2 * x + 1, clock * 4 }
         sphere { <image_width, image_height, 0> / 100, .5 }
         sphere { -<1, 2, 3> * <2, 2, 2> - z, 1e-3 }
         sphere { 0, 1. + 2.5E+1 }",
        &opts,
    );
    let s: Vec<(Vec3, f32)> = scene
        .objects
        .iter()
        .map(|o| match o.shape {
            Shape::Sphere { center, radius } => (center, radius),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(
        s,
        vec![
            (Vec3::new(7.0, 1.5, 6.0), 2.0),
            (Vec3::new(3.0, 1.0, 1.0), 1.0),
            (Vec3::new(8.0, 6.0, 0.0), 0.5),
            (Vec3::new(-2.0, -4.0, -7.0), 0.001),
            (Vec3::ZERO, 26.0),
        ]
    );
}

#[test]
fn declarations_of_float_vector_and_colour() {
    let scene = parse(
        r#"#include "colors.inc"
           #declare R = 2;
           #declare C = <1, 2, 3>;
           #declare Col = rgb <0.2, 0.4, 0.6>;
           #declare Half = Red * 0.5;
           #local Ft = color Blue filter 0.5;
           #declare R = R + 1;  // redeclaring replaces
           #declare X = 7;      // not the keyword x: declared names are case-sensitive
           sphere { C, R pigment { Col } }
           sphere { C * X, 1 pigment { Half } }
           sphere { 0, 1 pigment { color Ft } }"#,
    );
    assert_eq!(
        scene.objects[0].shape,
        Shape::Sphere {
            center: Vec3::new(1.0, 2.0, 3.0),
            radius: 3.0
        }
    );
    assert_eq!(scene.objects[0].pigment.color, Vec3::new(0.2, 0.4, 0.6));
    assert_eq!(
        scene.objects[1].shape,
        Shape::Sphere {
            center: Vec3::new(7.0, 14.0, 21.0),
            radius: 1.0
        }
    );
    assert_eq!(scene.objects[1].pigment.color, Vec3::new(0.5, 0.0, 0.0));
    assert_eq!(scene.objects[2].pigment.color, Vec3::Z);
    assert_eq!(scene.objects[2].pigment.filter, 0.5);
}

#[test]
fn comments_strings_and_numbers_lex() {
    let scene = parse(
        "/* outer /* nested */ still a comment */ // line comment
         sphere { <.5, 1e-3, 2.>, 1 } // trailing
         /**/",
    );
    assert_eq!(
        only_object(&scene).shape,
        Shape::Sphere {
            center: Vec3::new(0.5, 0.001, 2.0),
            radius: 1.0
        }
    );
    let mut lex = Lexer::new("a\n  \"s\\\"q\" 2e x");
    let kinds: Vec<(TokenKind, u32, u32)> = (0..5)
        .map(|_| {
            let t = lex.next_token().unwrap();
            (t.kind, t.pos.line, t.pos.col)
        })
        .collect();
    assert_eq!(
        kinds,
        vec![
            (TokenKind::Ident("a"), 1, 1),
            (TokenKind::Str("s\\\"q"), 2, 3),
            (TokenKind::Number(2.0), 2, 10),
            (TokenKind::Ident("e"), 2, 11),
            (TokenKind::Ident("x"), 2, 13),
        ]
    );
    assert_eq!(lex.next_token().unwrap().kind, TokenKind::Eof);
}

#[test]
fn colors_inc_table_matches_pov_ray() {
    assert_eq!(COLORS.len(), 130);
    assert_eq!(named_color("Red"), Some([1.0, 0.0, 0.0, 0.0, 0.0]));
    assert_eq!(named_color("Clear"), Some([1.0, 1.0, 1.0, 1.0, 0.0]));
    assert_eq!(named_color("Gray50"), Some([0.5, 0.5, 0.5, 0.0, 0.0]));
    assert_eq!(
        named_color("DarkSlateBlue"),
        Some([0.119608, 0.137255, 0.556863, 0.0, 0.0])
    );
    assert_eq!(named_color("OrangeRed"), Some([1.0, 0.25, 0.0, 0.0, 0.0]));
    assert_eq!(
        named_color("Very_Light_Purple"),
        Some([0.94, 0.81, 0.99, 0.0, 0.0])
    );
    assert_eq!(named_color("red"), None);
    // No duplicate names.
    for (i, (a, _)) in COLORS.iter().enumerate() {
        assert!(COLORS[i + 1..].iter().all(|(b, _)| a != b), "{a}");
    }
}

#[test]
fn normal_block_in_object_warns_with_position_and_is_skipped() {
    let src = "sphere { 0, 1\n  normal { bumps 0.5 scale 0.1 }\n  pigment { rgb 1 } }";
    let (scene, warnings) = parse_opts(src, &ParseOptions::new(320, 240));
    assert_eq!(
        warnings,
        vec!["2:3: unsupported `normal` in sphere: skipped".to_string()]
    );
    assert_eq!(only_object(&scene).pigment.color, Vec3::ONE);
}

#[test]
fn other_skipped_constructs_warn() {
    let src = r#"camera { location <0, 0, -5> look_at 0 aperture 0.3 blur_samples 20 }
light_source { <0, 9, 0> color rgb 1 spotlight point_at <0, 0, 0> }
global_settings { adc_bailout 0.01 }
sphere { 0, 1 no_shadow interior { ior 1.5 } hollow on
  pigment { checker color rgb 1 color rgb 0 scale 2 }
  finish { brilliance 2 phong 1 } }"#;
    let (scene, warnings) = parse_opts(src, &ParseOptions::new(320, 240));
    assert_eq!(
        warnings,
        vec![
            "1:40: unsupported `aperture` in camera: skipped",
            "1:53: unsupported `blur_samples` in camera: skipped",
            "2:38: unsupported `spotlight` in light_source: skipped",
            "2:48: unsupported `point_at` in light_source: skipped",
            "3:19: unsupported `adc_bailout` in global_settings: skipped",
            "4:15: unsupported `no_shadow` in sphere: skipped",
            "4:25: unsupported `interior` in sphere: skipped",
            "4:46: unsupported `hollow` in sphere: skipped",
            "5:13: unsupported `checker` in pigment (only flat colours and gradient with a color_map): \
             skipped",
            "6:12: unsupported `brilliance` in finish: skipped",
        ]
    );
    let o = only_object(&scene);
    assert_eq!(o.finish.phong, 1.0);
    assert_eq!(o.pigment.color, Vec3::ZERO);
}

#[test]
fn strict_mode_turns_the_normal_warning_into_an_error() {
    let src = "sphere { 0, 1\n  normal { bumps 0.5 }\n}";
    let opts = ParseOptions {
        strict: true,
        ..ParseOptions::new(320, 240)
    };
    let err = parse_scene::<4, 1, 4>(src, &opts, &mut |_| panic!("no warnings in strict mode"))
        .unwrap_err();
    assert_eq!(err.severity, Severity::Error);
    assert_eq!(
        err.to_string(),
        "2:3: unsupported `normal` in sphere (strict mode: not skipped)"
    );
}

#[test]
fn degenerate_triangle_is_dropped_with_a_warning() {
    let src = "triangle { <0, 0, 0>, <1, 1, 1>, <2, 2, 2> }\nsphere { 0, 1 }";
    let (scene, warnings) = parse_opts(src, &ParseOptions::new(320, 240));
    assert_eq!(
        warnings,
        vec!["1:1: degenerate triangle (zero area): dropped".to_string()]
    );
    assert_eq!(scene.objects.len(), 1);
}

#[test]
fn capacity_exactly_filled_is_fine() {
    let scene = parse_scene::<3, 2, 4>(
        "sphere { 0, 1 } sphere { 0, 1 } sphere { 0, 1 }
         light_source { 0 color 1 } light_source { 0 color 1 }",
        &ParseOptions::new(320, 240),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(scene.objects.len(), 3);
    assert_eq!(scene.lights.len(), 2);
}

#[test]
fn a_complete_pov_style_scene() {
    let src = r#"// A mountain by the sea (thesis §6.2.1), POV-Ray style.
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
"#;
    // The image size is the render's, stated once.
    let opts = hfray::RenderSettings::new(320, 200).parse_options();
    assert_eq!(opts, ParseOptions::new(320, 200));
    let (scene, w) = parse_opts(src, &opts);
    assert!(w.is_empty());
    assert!(close(scene.camera.right, Vec3::new(1.6, 0.0, 0.0)));
    assert_eq!(scene.camera.angle, Some(50.0));
    assert_eq!(scene.background, Vec3::new(0.196078, 0.6, 0.8));
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.objects[0].finish.reflection, Vec3::splat(0.6));
    assert_eq!(scene.objects[0].pigment.color, Vec3::new(0.1, 0.3, 0.5));
    assert_eq!(named(&scene), vec![(0, ImageFormat::Gif, "mountain.gif")]);
}

#[test]
fn directives_inside_blocks_and_hierarchy_are_accepted() {
    let scene = parse(
        r#"height_field { gif "a.gif"
             #declare W = 0.25;
             water_level W hierarchy on
             pigment { #include "colors.inc" color Green } }"#,
    );
    let o = only_object(&scene);
    assert_eq!(o.pigment.color, Vec3::Y);
    match o.shape {
        Shape::HeightField {
            source: Some(source),
            ..
        } => assert_eq!(source.water_level, 0.25),
        other => panic!("{other:?}"),
    }
}

#[test]
fn pov_image_map_block_in_height_field_warns() {
    let (scene, w) = parse_opts(
        r#"height_field { gif "a.gif" image_map { gif "a.gif" } }"#,
        &ParseOptions::new(320, 240),
    );
    assert_eq!(
        w,
        vec!["1:28: unsupported `image_map` in height_field: skipped"]
    );
    match only_object(&scene).shape {
        Shape::HeightField {
            source: Some(source),
            ..
        } => assert!(!source.palette_colors),
        other => panic!("{other:?}"),
    }
}
