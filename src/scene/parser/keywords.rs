//! Keywords: the table the parser matches identifiers against
//! (case-insensitively, as POV-Ray does) and the lists blocks check names in.

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kw {
    // top level
    Camera,
    LightSource,
    Background,
    GlobalSettings,
    HeightField,
    Plane,
    Sphere,
    Box,
    Cylinder,
    Cone,
    Triangle,
    // directives
    Declare,
    Local,
    Include,
    Version,
    // camera
    Perspective,
    Orthographic,
    Location,
    LookAt,
    Angle,
    Right,
    Up,
    Direction,
    Sky,
    // colours
    Color,
    Colour,
    Rgb,
    Rgbf,
    Rgbt,
    Rgbft,
    Red,
    Green,
    Blue,
    Filter,
    Transmit,
    Gray,
    // global settings
    AssumedGamma,
    MaxTraceLevel,
    AmbientLight,
    // object modifiers
    Scale,
    Rotate,
    Translate,
    Matrix,
    Transform,
    Pigment,
    Finish,
    Texture,
    ImageMap,
    Smooth,
    WaterLevel,
    Open,
    Hierarchy,
    QuickColor,
    Gradient,
    ColorMap,
    // height-field formats
    Gif,
    Png,
    Pgm,
    Ppm,
    Tga,
    Pot,
    // finish
    Ambient,
    Diffuse,
    Phong,
    PhongSize,
    Specular,
    Roughness,
    Reflection,
    // expression values
    X,
    Y,
    Z,
    Pi,
    Clock,
    ImageWidth,
    ImageHeight,
    True,
    False,
}

/// Keywords, lower case; matched case-insensitively.
const KEYWORDS: &[(&str, Kw)] = &[
    ("camera", Kw::Camera),
    ("light_source", Kw::LightSource),
    ("background", Kw::Background),
    ("global_settings", Kw::GlobalSettings),
    ("height_field", Kw::HeightField),
    ("plane", Kw::Plane),
    ("sphere", Kw::Sphere),
    ("box", Kw::Box),
    ("cylinder", Kw::Cylinder),
    ("cone", Kw::Cone),
    ("triangle", Kw::Triangle),
    ("declare", Kw::Declare),
    ("local", Kw::Local),
    ("include", Kw::Include),
    ("version", Kw::Version),
    ("perspective", Kw::Perspective),
    ("orthographic", Kw::Orthographic),
    ("location", Kw::Location),
    ("look_at", Kw::LookAt),
    ("angle", Kw::Angle),
    ("right", Kw::Right),
    ("up", Kw::Up),
    ("direction", Kw::Direction),
    ("sky", Kw::Sky),
    ("color", Kw::Color),
    ("colour", Kw::Colour),
    ("rgb", Kw::Rgb),
    ("rgbf", Kw::Rgbf),
    ("rgbt", Kw::Rgbt),
    ("rgbft", Kw::Rgbft),
    ("red", Kw::Red),
    ("green", Kw::Green),
    ("blue", Kw::Blue),
    ("filter", Kw::Filter),
    ("transmit", Kw::Transmit),
    ("gray", Kw::Gray),
    ("grey", Kw::Gray),
    ("assumed_gamma", Kw::AssumedGamma),
    ("max_trace_level", Kw::MaxTraceLevel),
    ("ambient_light", Kw::AmbientLight),
    ("scale", Kw::Scale),
    ("rotate", Kw::Rotate),
    ("translate", Kw::Translate),
    ("matrix", Kw::Matrix),
    ("transform", Kw::Transform),
    ("pigment", Kw::Pigment),
    ("finish", Kw::Finish),
    ("texture", Kw::Texture),
    ("image_map", Kw::ImageMap),
    ("smooth", Kw::Smooth),
    ("water_level", Kw::WaterLevel),
    ("open", Kw::Open),
    ("hierarchy", Kw::Hierarchy),
    ("quick_color", Kw::QuickColor),
    ("quick_colour", Kw::QuickColor),
    ("gradient", Kw::Gradient),
    ("color_map", Kw::ColorMap),
    ("colour_map", Kw::ColorMap),
    ("gif", Kw::Gif),
    ("png", Kw::Png),
    ("pgm", Kw::Pgm),
    ("ppm", Kw::Ppm),
    ("tga", Kw::Tga),
    ("pot", Kw::Pot),
    ("ambient", Kw::Ambient),
    ("diffuse", Kw::Diffuse),
    ("phong", Kw::Phong),
    ("phong_size", Kw::PhongSize),
    ("specular", Kw::Specular),
    ("roughness", Kw::Roughness),
    ("reflection", Kw::Reflection),
    ("x", Kw::X),
    ("y", Kw::Y),
    ("z", Kw::Z),
    ("pi", Kw::Pi),
    ("clock", Kw::Clock),
    ("image_width", Kw::ImageWidth),
    ("image_height", Kw::ImageHeight),
    ("true", Kw::True),
    ("yes", Kw::True),
    ("on", Kw::True),
    ("false", Kw::False),
    ("no", Kw::False),
    ("off", Kw::False),
];

pub(super) fn keyword(name: &str) -> Option<Kw> {
    // Bound: one pass over the fixed table.
    KEYWORDS
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(name))
        .map(|(_, kw)| *kw)
}

pub(super) fn is_keyword_exactly(name: &str) -> bool {
    KEYWORDS.iter().any(|(k, _)| *k == name)
}

pub(super) fn is_color_keyword(kw: Kw) -> bool {
    matches!(
        kw,
        Kw::Color
            | Kw::Colour
            | Kw::Rgb
            | Kw::Rgbf
            | Kw::Rgbt
            | Kw::Rgbft
            | Kw::Red
            | Kw::Green
            | Kw::Blue
            | Kw::Filter
            | Kw::Transmit
            | Kw::Gray
    )
}

pub(super) fn in_list(name: &str, list: &[&str]) -> bool {
    list.iter().any(|k| k.eq_ignore_ascii_case(name))
}
