//! Scene files from disk: parse a `.pov` file and load the height-field
//! images it names (relative to the scene file's folder), then build one
//! [`HeightField`] per `field_index` from what the file said about it (its
//! [`HeightFieldSource`](hfray::scene::HeightFieldSource) and transform).
//!
//! Ownership is split in three steps because the scene borrows its text and
//! the fields borrow their samples: the caller keeps the text, the parsed
//! [`Scene`] and the [`LoadedField`]s alive, in that order.

use std::path::{Path, PathBuf};

use hfray::scene::{parse_scene, ParseOptions, Scene};
use hfray::{HeightField, SkipGrid};

use super::images::{load_height_field, LoadedField};

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
    let err = |e: std::io::Error| format!("{}: {e}", path.display());
    let file = std::fs::File::open(path).map_err(err)?;
    if file.metadata().map_err(err)?.is_dir() {
        return Err(format!(
            "{}: is a directory, not a scene file",
            path.display()
        ));
    }
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(err)?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(format!(
            "{}: scene file is larger than {MAX_SCENE_BYTES} bytes (16 MiB), the most accepted",
            path.display()
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "{}: scene file is not UTF-8 text (invalid byte at offset {})",
            path.display(),
            e.utf8_error().valid_up_to()
        )
    })
}

/// Parses `text` (read from `path`); warnings go to `warn` already
/// formatted as `FILE:LINE:COL: message`, errors come back formatted so.
pub fn parse_file_scene<'src>(
    path: &Path,
    text: &'src str,
    options: &ParseOptions,
    warn: &mut dyn FnMut(String),
) -> Result<FileScene<'src>, String> {
    let shown = path.display().to_string();
    parse_scene(text, options, &mut |d| warn(format!("{shown}:{d}")))
        .map_err(|d| format!("{shown}:{d}"))
}

/// Loads every height-field image the scene names, in `field_index` order,
/// resolving paths against the scene file's folder, and builds each one's
/// skip pyramid (walked by default; hits are the same as the flat walk's).
pub fn load_fields(scene: &FileScene<'_>, scene_path: &Path) -> Result<Vec<LoadedField>, String> {
    let dir = scene_path.parent().unwrap_or(Path::new("."));
    let mut named: Vec<_> = scene.height_field_sources().collect();
    named.sort_by_key(|(index, _, _)| *index);
    named
        .into_iter()
        .map(|(_, source, _)| {
            let resolved: PathBuf = dir.join(source.path);
            let mut field =
                load_height_field(&resolved, source.format).map_err(|e| e.to_string())?;
            field
                .build_skip()
                .map_err(|e| format!("{}: {e}", resolved.display()))?;
            Ok(field)
        })
        .collect()
}

/// One [`HeightField`] per loaded image: the one place a parsed height field
/// becomes the field the renderer uses, with the file's transform, water
/// level and (for palette colouring) palette.
pub fn build_fields<'d>(
    scene: &FileScene<'_>,
    loaded: &'d [LoadedField],
) -> Result<Vec<HeightField<'d>>, String> {
    let mut fields: Vec<Option<HeightField<'d>>> = vec![None; loaded.len()];
    for (field_index, source, transform) in scene.height_field_sources() {
        let path = source.path;
        let data = loaded
            .get(field_index)
            .ok_or_else(|| format!("{path}: height field {field_index} was not loaded"))?;
        let samples = data.samples();
        let mut field = HeightField::new(samples, data.width(), data.depth(), data.convention())
            .map_err(|e| format!("{path}: {e}"))?
            .with_water_level(source.water_level)
            .map_err(|e| format!("{path}: {e}"))?
            .try_with_transform(*transform)
            .map_err(|e| format!("{path}: {e}"))?;
        if let Some(bytes) = data.skip_bytes() {
            let grid =
                SkipGrid::from_precomputed(bytes, &field).map_err(|e| format!("{path}: {e}"))?;
            field = field.with_skip(grid).map_err(|e| format!("{path}: {e}"))?;
        }
        if source.palette_colors {
            match data.palette() {
                Some(palette) => {
                    field = field
                        .with_palette(palette)
                        .map_err(|e| format!("{path}: {e}"))?
                }
                None => {
                    return Err(format!(
                        "{path}: image_map (palette colouring) needs an indexed image (GIF or palette PNG)"
                    ))
                }
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
