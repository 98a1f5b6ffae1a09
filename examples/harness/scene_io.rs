//! Scene files from disk: parse a `.pov` file and load the height-field
//! images it names (relative to the scene file's folder), then build one
//! [`HeightField`] per `field_index` from what the file said about it (its
//! [`HeightFieldSource`](hfray::scene::HeightFieldSource), placement included).
//!
//! Ownership is split in three steps because the scene borrows its text and
//! the fields borrow their samples: the caller keeps the text, the parsed
//! [`Scene`] and the [`LoadedField`]s alive, in that order.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use hfray::scene::{
    parse_scene_located, Echo, HeightFieldSource, ImageFormat, ParseOptions, Pos, Scene, Shape,
};
use hfray::HeightField;

use super::images::{load_height_field_within, DecodeBudget, LoadedField};

/// Objects and lights a scene file may hold in the harness.
pub const OBJECTS: usize = 64;
/// Light sources a scene file may hold in the harness.
pub const LIGHTS: usize = 16;

/// A scene parsed by the harness.
pub type FileScene<'src> = Scene<'src, OBJECTS, LIGHTS>;

/// The largest scene file read, in bytes (16 MiB: hundreds of times any
/// scene the subset can express, whose objects are capped at [`OBJECTS`]).
/// Reading stops there, so a huge file, or an endless one such as
/// `/dev/zero` or a pipe, is an error rather than an exhausted memory.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// Reads a scene file's text (at most [`MAX_SCENE_BYTES`]); the error names
/// the file.
pub fn read_scene_text(path: &Path) -> Result<String, String> {
    use std::io::Read;
    let err = |e: std::io::Error| format!("{}: {e}", shown_path(path));
    let file = std::fs::File::open(path).map_err(err)?;
    if file.metadata().map_err(err)?.is_dir() {
        return Err(format!(
            "{}: is a directory, not a scene file",
            shown_path(path)
        ));
    }
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(err)?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(format!(
            "{}: scene file is larger than {MAX_SCENE_BYTES} bytes (16 MiB), the most accepted",
            shown_path(path)
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "{}: scene file is not UTF-8 text (invalid byte at offset {})",
            shown_path(path),
            e.utf8_error().valid_up_to()
        )
    })
}

/// Where a scene came from: its file, and where each of its objects was
/// written, so that a problem found after parsing (an image that cannot be
/// read, a placement that cannot be inverted, a degenerate shape) is
/// reported as `FILE:LINE:COL` at the object.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SceneSource {
    file: PathBuf,
    /// The position of each object's keyword, by index in `scene.objects`.
    positions: Vec<Pos>,
}

impl SceneSource {
    /// A scene read from `file`, with no object positions known.
    pub fn new(file: &Path) -> Self {
        SceneSource {
            file: file.to_path_buf(),
            positions: Vec::new(),
        }
    }

    /// The scene file.
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// `FILE:LINE:COL` of object `object` (`FILE: object N` when its
    /// position is unknown).
    pub fn at(&self, object: usize) -> String {
        let file = shown_path(&self.file);
        match self.positions.get(object) {
            Some(p) => format!("{file}:{}:{}", p.line, p.col),
            None if file.is_empty() => format!("object {object}"),
            None => format!("{file}: object {object}"),
        }
    }

    /// The file an image named in the scene resolves to (relative names
    /// are relative to the scene file's folder).
    pub fn resolve(&self, image: &str) -> PathBuf {
        self.file.parent().unwrap_or(Path::new(".")).join(image)
    }
}

/// A path as messages show it: at most 80 characters, control characters
/// escaped ([`Echo`]), since paths come from scene files and command lines.
pub fn shown_path(path: &Path) -> String {
    Echo(&path.to_string_lossy()).to_string()
}

/// Parses `text` (read from `path`); warnings go to `warn` already
/// formatted as `FILE:LINE:COL: message`, errors come back formatted so.
pub fn parse_file_scene<'src>(
    path: &Path,
    text: &'src str,
    options: &ParseOptions,
    warn: &mut dyn FnMut(String),
) -> Result<FileScene<'src>, String> {
    parse_file_scene_located(path, text, options, warn).map(|(scene, _)| scene)
}

/// [`parse_file_scene`], also returning where each object was written.
pub fn parse_file_scene_located<'src>(
    path: &Path,
    text: &'src str,
    options: &ParseOptions,
    warn: &mut dyn FnMut(String),
) -> Result<(FileScene<'src>, SceneSource), String> {
    let mut source = SceneSource::new(path);
    let shown = shown_path(path);
    let scene = parse_scene_located(
        text,
        options,
        &mut |d| warn(format!("{shown}:{d}")),
        &mut |object, pos| {
            source.positions.resize(object, Pos::default());
            source.positions.push(pos);
        },
    )
    .map_err(|d| format!("{shown}:{d}"))?;
    Ok((scene, source))
}

/// Every height-field object: (object index, field index, what the file
/// said about it).
fn field_objects<'s, 'src>(
    scene: &'s FileScene<'src>,
) -> impl Iterator<Item = (usize, usize, HeightFieldSource<'src>)> + 's {
    scene
        .objects
        .iter()
        .enumerate()
        .filter_map(|(i, o)| match o.shape {
            Shape::HeightField {
                field_index,
                source: Some(hf),
                ..
            } => Some((i, field_index, hf)),
            _ => None,
        })
}

/// The files a scene reads: the scene file and every image it names
/// (includes are built in; none is read from disk).
pub fn input_files(scene: &FileScene<'_>, source: &SceneSource) -> Vec<PathBuf> {
    let mut files = vec![source.file.clone()];
    files.extend(field_objects(scene).map(|(_, _, hf)| source.resolve(hf.path)));
    files
}

/// Loads every height-field image the scene names, in `field_index` order,
/// resolving paths against the scene file's folder, and builds each one's
/// skip pyramid (walked by default; hits are the same as the flat walk's),
/// within a [`DecodeBudget::default`].
pub fn load_fields(
    scene: &FileScene<'_>,
    scene_path: &Path,
) -> Result<Vec<Arc<LoadedField>>, String> {
    load_fields_within(
        scene,
        &SceneSource::new(scene_path),
        &mut DecodeBudget::default(),
    )
}

/// [`load_fields`], charging every image to `budget` and reporting errors
/// at the object that names the image. Objects that name the same file
/// (the same device and inode) in the same format share one decode.
pub fn load_fields_within(
    scene: &FileScene<'_>,
    source: &SceneSource,
    budget: &mut DecodeBudget,
) -> Result<Vec<Arc<LoadedField>>, String> {
    let mut named: Vec<_> = field_objects(scene).collect();
    named.sort_by_key(|&(_, field_index, _)| field_index);
    let mut decoded: Vec<(FileId, ImageFormat, Arc<LoadedField>)> = Vec::new();
    let mut fields = Vec::with_capacity(named.len());
    for (object, _, hf) in named {
        let (format, resolved) = (hf.format, source.resolve(hf.path));
        let at = |e: String| format!("{}: {e}", source.at(object));
        let id = file_id(&resolved);
        let shared = decoded
            .iter()
            .find(|(other, f, _)| id.is_some() && *other == id && *f == format);
        if let Some((_, _, field)) = shared {
            fields.push(Arc::clone(field));
            continue;
        }
        let mut field =
            load_height_field_within(&resolved, format, budget).map_err(|e| at(e.to_string()))?;
        field
            .build_skip(budget)
            .map_err(|e| at(format!("{}: {e}", shown_path(&resolved))))?;
        let field = Arc::new(field);
        decoded.push((id, format, Arc::clone(&field)));
        fields.push(field);
    }
    Ok(fields)
}

/// A file's identity (device and inode), when it can be read.
type FileId = Option<(u64, u64)>;

fn file_id(path: &Path) -> FileId {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        None
    }
}

/// One [`HeightField`] per loaded image: the one place a parsed height field
/// becomes the field the renderer uses, with the file's transform, water
/// level and (for palette colouring) palette.
pub fn build_fields<'d>(
    scene: &FileScene<'_>,
    loaded: &'d [Arc<LoadedField>],
) -> Result<Vec<HeightField<'d>>, String> {
    build_fields_located(scene, loaded, &SceneSource::default())
}

/// [`build_fields`], reporting errors at the object (`FILE:LINE:COL`).
pub fn build_fields_located<'d>(
    scene: &FileScene<'_>,
    loaded: &'d [Arc<LoadedField>],
    source: &SceneSource,
) -> Result<Vec<HeightField<'d>>, String> {
    let mut fields: Vec<Option<HeightField<'d>>> = vec![None; loaded.len()];
    for (i, field_index, hf) in field_objects(scene) {
        let path = hf.path;
        let at = |e: &dyn std::fmt::Display| {
            format!("{}: height_field \"{}\": {e}", source.at(i), Echo(path))
        };
        let data = loaded
            .get(field_index)
            .ok_or_else(|| at(&format!("height field {field_index} was not loaded")))?;
        let samples = data.samples();
        let mut field = HeightField::new(samples, data.width(), data.depth(), data.convention())
            .map_err(|e| at(&e))?
            .with_water_level(hf.water_level)
            .map_err(|e| at(&e))?
            .try_with_transform(hf.transform)
            .map_err(|e| at(&e))?;
        if let Some(bytes) = data.skip_bytes() {
            field = field.with_skip(bytes).map_err(|e| at(&e))?;
        }
        if hf.palette_colors {
            match data.palette() {
                Some(palette) => field = field.with_palette(palette).map_err(|e| at(&e))?,
                None => return Err(at(
                    &"image_map (palette colouring) needs an indexed image (GIF or palette PNG)",
                )),
            }
        }
        fields[field_index] = Some(field);
    }
    fields
        .into_iter()
        .enumerate()
        .map(|(i, f)| f.ok_or_else(|| format!("height field {i} has no object")))
        .collect()
}
