//! `render`: a POV-Ray-style scene file to an image, streamed row by row.
//!
//! ```text
//! cargo run --release --example render -- SCENE.pov -o OUT.tga [OPTIONS]
//! cargo run --release --example render -- --help
//! ```
//!
//! `--walk` chooses how height fields are crossed (default: the skip
//! pyramid, `hierarchy`) and `--coherence` whether primary rays resume
//! where the ray below them stopped (default `on`; it pays with a level
//! camera). Every choice gives the same image, only the work differs: see
//! it with `--stats` (`cells`, `blocks`, `resumed`). With coherence on and
//! a level camera (`up` vertical), TGA and PFM files are rendered bottom
//! row first (TGA then has its bottom-left origin; PFM stores rows that way
//! anyway); PNG stays top-down, as it must be written, so its rays do not
//! resume. Other cameras render top-down, as without coherence.
//!
//! The output type follows the extension: `.tga` (uncompressed 24-bit),
//! `.png`, or `.pfm` with `--aov depth` (distance to the first hit along the
//! normalised camera ray, `+inf` for none). Rows are written as they are
//! finished; with `--threads N` the image is cut into bands of rows that
//! threads render in parallel, still written in order through a bounded
//! queue.
//!
//! The output is written to a new file of a random name beside it,
//! `.NAME.partial-PID-XXXXXX` (created exclusively, so a planted file or
//! link of that name is never opened), and renamed over `NAME` when
//! complete: an error or an interrupt never leaves a partial image under
//! the requested name, and an existing file of that name stays as it was
//! until the new one replaces it. A run killed outright (SIGKILL, a power
//! cut) leaves its `.NAME.partial-PID-XXXXXX` behind; the name says which
//! output and which process it was, and nothing deletes such files
//! automatically (another run may still be writing one). An output that
//! is one of the scene's inputs (the scene file, an image it names) is
//! refused.
//!
//! Errors print `error: FILE:LINE:COL: message` (or `error: message`) and
//! exit with status 1. An interrupt (Ctrl-C / SIGINT, SIGTERM, SIGHUP)
//! removes the temporary file, prints `interrupted` and exits with status
//! 130. A file-size limit (`ulimit -f`) is an error naming it, not a
//! SIGXFSZ death.

#[path = "harness/mod.rs"]
mod harness;

use std::io::{IsTerminal, Write};
use std::ops::{ControlFlow, Range};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::{mpsc, Mutex, MutexGuard};
use std::time::Instant;

use clap::Parser;
use harness::alloc_count::CountingAlloc;
use harness::images::{DecodeBudget, DEFAULT_DECODE_BUDGET};
use harness::pfm::PfmWriter;
use harness::png_out::PngWriter;
use harness::scene_io::{
    build_fields_located, input_files, load_fields_within, parse_file_scene_located,
    read_scene_text, shown_path, FileScene, SceneSource,
};
use harness::tga::TgaWriter;
use hfray::pixel::Rgb888;
use hfray::render::{
    render_coherent, render_depth_coherent, RenderError, RenderSettings, RowOrder, Stats,
};
use hfray::scene::ParseOptions;
use hfray::{render, render_depth, Camera, ColumnHint, HeightField, Traversal};

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc::new();

/// Rows a thread renders before handing the band on.
const BAND_ROWS: u32 = 8;

/// The largest side: a row of pixels per thread stays small, and
/// width × height × aa² fits comfortably in u64 counters.
const MAX_SIDE: u32 = 1 << 16;

/// Threads per core at most: more only add memory and switching.
const THREADS_PER_CORE: u32 = 4;

/// Memory for rows in flight between the render threads and the writer
/// (each thread's line, and the rows queued behind it).
const ROWS_IN_FLIGHT_BYTES: u64 = 64 << 20;

/// Render a POV-Ray scene file to an image, streamed row by row.
#[derive(Debug, Parser)]
#[command(name = "render", max_term_width = 100)]
struct Options {
    /// The scene file (POV-Ray subset; images it names are read relative
    /// to its folder).
    #[arg(value_name = "SCENE.pov")]
    scene: PathBuf,
    /// The image to write: .tga, .png, or .pfm with --aov depth. Written
    /// under a temporary name and renamed when complete.
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// Image width in pixels (1..=65536).
    #[arg(long, value_name = "W", default_value_t = 320, value_parser = side)]
    width: u32,
    /// Image height in pixels (1..=65536).
    #[arg(long, value_name = "H", default_value_t = 200, value_parser = side)]
    height: u32,
    /// N×N supersampling per pixel (1..=16; the thesis used 2).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=i64::from(hfray::render::MAX_AA)))]
    aa: u32,
    /// Threads rendering bands of 8 rows in parallel (1..=256; at most 4
    /// per core and one per band are used, which is reported).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256))]
    threads: u32,
    /// Render only rows A..B (an image B−A rows high), to split a frame
    /// across machines. Default: every row.
    #[arg(long, value_name = "A..B", value_parser = parse_rows)]
    rows: Option<Range<u32>>,
    /// An animation of N frames, `clock` going from 0 to 1, written to
    /// numbered files (out_0000.tga, ...).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    frames: u32,
    /// Write an arbitrary output variable instead of colour: `depth`
    /// (distance to the first hit, into a .pfm).
    #[arg(long, value_name = "AOV", value_parser = ["depth"])]
    aov: Option<String>,
    /// Memory for decoded height-field images, in MiB, across all of the
    /// scene's images (samples and skip pyramids); an image that does not
    /// fit is an error before anything is allocated for it.
    #[arg(long, value_name = "MIB", default_value_t = DEFAULT_DECODE_BUDGET >> 20, value_parser = clap::value_parser!(u64).range(1..=1 << 20))]
    max_image_mib: u64,
    /// Print one line of statistics on stderr.
    #[arg(long)]
    stats: bool,
    /// Make skipped (unsupported) scene constructs errors.
    #[arg(long)]
    strict: bool,
    /// No warnings, notes or progress.
    #[arg(long)]
    quiet: bool,
    /// How height fields are crossed: `flat` (every cell), `blocks` (the
    /// skip pyramid, block by block) or `hierarchy` (the hierarchical DDA
    /// over the pyramid). Every choice writes the same image.
    #[arg(long, value_name = "WALK", default_value = "hierarchy", value_parser = parse_walk)]
    walk: Traversal,
    /// Whether a primary ray resumes where the ray below it stopped (exact;
    /// it pays with a level camera). The same image either way.
    #[arg(long, value_name = "on|off", default_value = "on", value_parser = parse_on_off, action = clap::ArgAction::Set)]
    coherence: bool,
}

fn parse_walk(value: &str) -> Result<Traversal, String> {
    match value {
        "flat" => Ok(Traversal::Flat),
        "blocks" => Ok(Traversal::Blocks),
        "hierarchy" => Ok(Traversal::Hierarchy),
        _ => Err(format!("'{value}' is not flat, blocks or hierarchy")),
    }
}

fn parse_on_off(value: &str) -> Result<bool, String> {
    match value {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("'{value}' is not on or off")),
    }
}

impl Options {
    fn depth_aov(&self) -> bool {
        self.aov.is_some()
    }

    /// The image these options render (whole, top-down): the one source of
    /// its size, for the parser's `image_width`/`image_height` as well.
    fn settings(&self) -> RenderSettings {
        RenderSettings::new(self.width, self.height).with_aa(self.aa)
    }

    /// Checks what clap cannot: rows against the height, the output's
    /// type and folder.
    fn check(&self) -> Result<(), String> {
        if let Some(rows) = &self.rows {
            if rows.end > self.height {
                return Err(format!(
                    "--rows {}..{} goes past the image height {}",
                    rows.start, rows.end, self.height
                ));
            }
        }
        let ext = extension(&self.output);
        match (ext.as_str(), self.depth_aov()) {
            ("tga" | "png", false) | ("pfm", true) => {}
            ("pfm", false) => {
                return Err("a .pfm output holds the depth AOV: add --aov depth".into())
            }
            (_, true) => return Err("--aov depth writes a .pfm file".into()),
            _ => {
                return Err(format!(
                    "{}: unknown output type (use .tga, .png, or .pfm with --aov depth)",
                    shown_path(&self.output)
                ))
            }
        }
        let folder = output_folder(&self.output);
        if !folder.is_dir() {
            return Err(format!(
                "{}: the output folder {} does not exist (or is not a folder)",
                shown_path(&self.output),
                shown_path(folder)
            ));
        }
        Ok(())
    }
}

fn side(value: &str) -> Result<u32, String> {
    let n: u32 = value
        .parse()
        .map_err(|_| format!("'{value}' is not a whole number"))?;
    if !(1..=MAX_SIDE).contains(&n) {
        return Err(format!("{n} is outside 1..={MAX_SIDE}"));
    }
    Ok(n)
}

fn parse_rows(value: &str) -> Result<Range<u32>, String> {
    let (a, b) = value
        .split_once("..")
        .ok_or_else(|| format!("'{value}' is not of the form A..B"))?;
    let a: u32 = a.parse().map_err(|_| format!("'{a}' is not a row"))?;
    let b: u32 = b.parse().map_err(|_| format!("'{b}' is not a row"))?;
    if a >= b {
        return Err(format!("{a}..{b} is empty"));
    }
    Ok(a..b)
}

/// The folder `output` is written in.
fn output_folder(output: &Path) -> &Path {
    match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

fn extension(p: &Path) -> String {
    p.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

/// The row order `o`'s output is written in: bottom-up where the format
/// allows it and coherence can use it (a level camera), else top-down.
fn row_order(o: &Options, scene: &FileScene<'_>) -> RowOrder {
    let level = Camera::new(&scene.camera, o.width, o.height).is_ok_and(|c| c.level_columns());
    match extension(&o.output).as_str() {
        "tga" | "pfm" if o.coherence && level => RowOrder::BottomUp,
        _ => RowOrder::TopDown,
    }
}

type File = std::io::BufWriter<std::fs::File>;

/// The output file, written row by row in order as rows leave the renderer.
enum Output {
    Tga(TgaWriter<File>),
    Png(Box<PngWriter<File>>),
    Pfm(PfmWriter<File>),
}

/// An output and the name its errors report.
struct Sink {
    output: Output,
    path: PathBuf,
    bytes: Vec<[u8; 3]>,
}

/// An I/O error on `path`, saying so plainly when it is the file-size
/// limit (`ulimit -f`: EFBIG, with SIGXFSZ ignored so the write fails
/// instead of killing the process).
fn io_err(path: &Path, e: std::io::Error) -> String {
    if e.raw_os_error() == Some(libc::EFBIG) {
        return format!(
            "{}: the file-size limit (ulimit -f) was reached while writing the image; \
             nothing was written under this name",
            shown_path(path)
        );
    }
    format!("{}: {e}", shown_path(path))
}

impl Sink {
    /// Writes to `file` for the final `path`, typed by `path`'s extension.
    fn create(
        path: &Path,
        file: std::fs::File,
        width: u32,
        height: u32,
        order: RowOrder,
    ) -> Result<Sink, String> {
        let err = |e| io_err(path, e);
        let file = std::io::BufWriter::new(file);
        let bottom_up = order == RowOrder::BottomUp;
        let output = match extension(path).as_str() {
            "tga" if bottom_up => {
                Output::Tga(TgaWriter::new_bottom_up(file, width, height).map_err(err)?)
            }
            "tga" => Output::Tga(TgaWriter::new(file, width, height).map_err(err)?),
            "png" => Output::Png(Box::new(PngWriter::new(file, width, height).map_err(err)?)),
            _ if bottom_up => {
                Output::Pfm(PfmWriter::new_bottom_up(file, width, height).map_err(err)?)
            }
            _ => Output::Pfm(PfmWriter::new(file, width, height).map_err(err)?),
        };
        Ok(Sink {
            output,
            path: path.to_path_buf(),
            bytes: Vec::new(),
        })
    }

    fn write(&mut self, row: &Row) -> Result<(), String> {
        if let Row::Color(pixels) = row {
            self.bytes.clear();
            self.bytes.extend(pixels.iter().map(|p| p.0));
        }
        let result = match (&mut self.output, row) {
            (Output::Tga(w), Row::Color(_)) => w.write_row(&self.bytes),
            (Output::Png(w), Row::Color(_)) => w.write_row(&self.bytes),
            (Output::Pfm(w), Row::Depth(depths)) => w.write_row(depths),
            _ => return Err("internal error: row of the wrong kind for this output".into()),
        };
        result.map_err(|e| io_err(&self.path, e))
    }

    fn finish(self) -> Result<(), String> {
        let err = |e| io_err(&self.path, e);
        match self.output {
            Output::Tga(w) => w.finish().and_then(|mut f| f.flush()).map_err(err),
            Output::Png(w) => w.finish().map_err(err),
            Output::Pfm(w) => w.finish().and_then(|mut f| f.flush()).map_err(err),
        }
    }
}

/// A row finished by a worker.
enum Row {
    Color(Vec<Rgb888>),
    Depth(Vec<f32>),
}

/// Shows `rendering N%` on a terminal, at most a hundred times.
struct Progress {
    enabled: bool,
    total: u32,
    done: u32,
    shown: u32,
}

impl Progress {
    fn new(quiet: bool, total: u32) -> Self {
        Progress {
            enabled: !quiet && std::io::stderr().is_terminal(),
            total,
            done: 0,
            shown: u32::MAX,
        }
    }
    fn row(&mut self) {
        self.done += 1;
        if !self.enabled {
            return;
        }
        let pct = (self.done as u64 * 100 / self.total.max(1) as u64) as u32;
        if pct != self.shown {
            self.shown = pct;
            eprint!("\rrendering {pct:3}%");
            if self.done == self.total {
                eprint!("\r              \r");
            }
        }
    }
}

/// How many threads render, and how many finished rows each may queue.
#[derive(Debug, Clone, Copy)]
struct Threads {
    count: u32,
    queue_rows: usize,
}

impl Threads {
    /// The threads `o` asks for, capped at one per band of rows, at
    /// [`THREADS_PER_CORE`] per core, and at what keeps the rows in flight
    /// (each thread's line, the row it is sending and its queue) within
    /// [`ROWS_IN_FLIGHT_BYTES`]. A cap is said on stderr unless `--quiet`.
    fn plan(o: &Options, rows: u32) -> Threads {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get() as u32);
        let pixel_bytes = if o.depth_aov() {
            size_of::<f32>()
        } else {
            size_of::<Rgb888>()
        } as u64;
        let row_bytes = u64::from(o.width) * pixel_bytes;
        let caps = [
            (
                rows.div_ceil(BAND_ROWS),
                format!("one per band of {BAND_ROWS} rows"),
            ),
            (
                THREADS_PER_CORE * cores,
                format!("{THREADS_PER_CORE} per core on {cores} cores"),
            ),
            (
                (ROWS_IN_FLIGHT_BYTES / (3 * row_bytes)).clamp(1, 256) as u32,
                format!(
                    "rows of {} in flight kept within {} MiB",
                    o.width,
                    ROWS_IN_FLIGHT_BYTES >> 20
                ),
            ),
        ];
        let mut count = o.threads;
        let mut why = None;
        for (cap, reason) in caps {
            if cap.max(1) < count {
                count = cap.max(1);
                why = Some(reason);
            }
        }
        if let (Some(why), false) = (why, o.quiet) {
            eprintln!("note: --threads {} reduced to {count} ({why})", o.threads);
        }
        let queue_rows = (ROWS_IN_FLIGHT_BYTES / (u64::from(count) * row_bytes))
            .saturating_sub(2)
            .clamp(1, 2 * u64::from(BAND_ROWS)) as usize;
        Threads { count, queue_rows }
    }
}

/// A render error, at the object that caused it when there is one.
fn located(e: &RenderError, source: &SceneSource) -> String {
    match *e {
        RenderError::Shape { object, error } => format!("{}: {error}", source.at(object)),
        RenderError::MissingField { object, .. } | RenderError::NotBuilt { object } => {
            format!("{}: {e}", source.at(object))
        }
        _ => e.to_string(),
    }
}

/// Renders `rows` of the frame on `threads` (bands of [`BAND_ROWS`]
/// handed out round-robin), passing rows to `sink` in order.
#[allow(clippy::too_many_arguments)]
fn render_rows(
    scene: &FileScene<'_>,
    source: &SceneSource,
    fields: &[HeightField<'_>],
    o: &Options,
    threads: Threads,
    rows: Range<u32>,
    sink: &mut Sink,
    progress: &mut Progress,
) -> Result<Stats, String> {
    let order = row_order(o, scene);
    let base = o.settings().with_order(order);
    let Threads {
        count: threads,
        queue_rows,
    } = threads;
    let mut bands: Vec<Range<u32>> = rows
        .clone()
        .step_by(BAND_ROWS as usize)
        .map(|a| a..(a + BAND_ROWS).min(rows.end))
        .collect();
    if order == RowOrder::BottomUp {
        bands.reverse();
    }
    std::thread::scope(|s| {
        // One bounded queue per worker: a worker runs at most
        // `queue_rows` rows ahead of the writer.
        let mut receivers = Vec::new();
        let mut handles = Vec::new();
        for k in 0..threads as usize {
            let (tx, rx) = mpsc::sync_channel::<Result<Row, String>>(queue_rows);
            receivers.push(rx);
            let my_bands: Vec<Range<u32>> = bands
                .iter()
                .skip(k)
                .step_by(threads as usize)
                .cloned()
                .collect();
            let base = base.clone();
            let depth = o.depth_aov();
            let coherence = o.coherence;
            handles.push(s.spawn(move || -> Stats {
                let mut total = Stats::default();
                // Kept from band to band: this worker's bands come one above
                // the other.
                let mut hints = vec![ColumnHint::new(); base.column_hints_needed(fields.len())];
                for band in my_bands {
                    let settings = base.clone().with_rows(band);
                    let result = if depth {
                        let mut line = vec![0f32; settings.width as usize];
                        let mut sink = |_, r: &[f32]| send(&tx, Row::Depth(r.to_vec()));
                        if coherence {
                            render_depth_coherent(
                                scene, fields, &settings, &mut line, &mut hints, &mut sink,
                            )
                        } else {
                            render_depth(scene, fields, &settings, &mut line, &mut sink)
                        }
                    } else {
                        let mut line = vec![Rgb888::default(); settings.width as usize];
                        let mut sink = |_, r: &[Rgb888]| send(&tx, Row::Color(r.to_vec()));
                        if coherence {
                            render_coherent(
                                scene, fields, &settings, &mut line, &mut hints, &mut sink,
                            )
                        } else {
                            render(scene, fields, &settings, &mut line, &mut sink)
                        }
                    };
                    match result {
                        Ok(stats) => {
                            total.merge(&stats);
                            if stats.cancelled {
                                break;
                            }
                        }
                        Err(e) => {
                            let _ = tx.send(Err(located(&e, source)));
                            break;
                        }
                    }
                }
                total
            }));
        }
        let mut failure = None;
        'bands: for (b, band) in bands.iter().enumerate() {
            let rx = &receivers[b % threads as usize];
            for _ in band.clone() {
                let row = match rx.recv() {
                    Ok(Ok(row)) => row,
                    Ok(Err(e)) => {
                        failure = Some(e);
                        break 'bands;
                    }
                    Err(_) => {
                        failure = Some("a render thread stopped early".to_string());
                        break 'bands;
                    }
                };
                if let Err(e) = sink.write(&row) {
                    failure = Some(e);
                    break 'bands;
                }
                progress.row();
            }
        }
        // Dropping the receivers makes every worker's next send fail, so
        // they stop at once after an error.
        drop(receivers);
        let mut stats = Stats::default();
        for h in handles {
            match h.join() {
                Ok(s) => stats.merge(&s),
                Err(_) => {
                    failure.get_or_insert_with(|| "a render thread panicked".into());
                }
            }
        }
        match failure {
            Some(e) => Err(e),
            None => Ok(stats),
        }
    })
}

fn send(tx: &mpsc::SyncSender<Result<Row, String>>, row: Row) -> ControlFlow<()> {
    match tx.send(Ok(row)) {
        Ok(()) => ControlFlow::Continue(()),
        Err(_) => ControlFlow::Break(()),
    }
}

/// `out.tga` → `out_0003.tga` for frame 3 of a sequence.
fn frame_path(output: &Path, frame: u32, frames: u32) -> PathBuf {
    if frames == 1 {
        return output.to_path_buf();
    }
    let digits = frames.to_string().len().max(4);
    let stem = output
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("frame");
    let ext = extension(output);
    output.with_file_name(format!("{stem}_{frame:0digits$}.{ext}"))
}

/// The temporary file being written, if any. It is created, renamed and
/// removed only while this lock is held, and the interrupt handler takes
/// the lock and never gives it back (it exits), so an interrupt can never
/// land between creating the file and recording it, or leave it behind.
static PARTIAL: Mutex<Option<PathBuf>> = Mutex::new(None);

fn partial() -> MutexGuard<'static, Option<PathBuf>> {
    // A poisoned lock still holds the right path.
    PARTIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// A new file to write `output` under, beside it: created exclusively
/// (`O_CREAT | O_EXCL`, so neither a planted file nor a symlink of that
/// name is ever opened) with a random part in its name,
/// `.NAME.partial-PID-XXXXXX`, and recorded for the interrupt handler.
/// Dropping the returned path removes the file.
fn create_partial(output: &Path) -> Result<(std::fs::File, tempfile::TempPath), String> {
    let name = output
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    let mut guard = partial();
    let file = tempfile::Builder::new()
        .prefix(&format!(".{name}.partial-{}-", std::process::id()))
        .rand_bytes(6)
        // As `File::create` would (the umask applies): the image is for
        // the user's tools, not private.
        .permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666))
        .tempfile_in(output_folder(output))
        .map_err(|e| io_err(output, e))?;
    let (file, path) = file.into_parts();
    *guard = Some(path.to_path_buf());
    Ok((file, path))
}

/// Renames the finished temporary file over `output` (atomically: readers
/// see the old file or the new one), or removes it on failure.
fn publish(temp: tempfile::TempPath, output: &Path) -> Result<(), String> {
    let mut guard = partial();
    let renamed = temp.persist(output);
    *guard = None;
    // On failure the error holds the path; dropping it removes the file.
    renamed.map_err(|e| io_err(output, e.error))
}

/// Removes the temporary file (after an error).
fn discard(temp: tempfile::TempPath) {
    let mut guard = partial();
    drop(temp);
    *guard = None;
}

/// Refuses an output that is one of the scene's inputs: the same file
/// (device and inode) when it exists, the same path when it does not yet.
fn refuse_input_as_output(output: &Path, inputs: &[PathBuf]) -> Result<(), String> {
    use std::os::unix::fs::MetadataExt;
    let id = |p: &Path| std::fs::metadata(p).ok().map(|m| (m.dev(), m.ino()));
    let full = |p: &Path| -> Option<PathBuf> {
        let folder = std::fs::canonicalize(output_folder(p)).ok()?;
        Some(folder.join(p.file_name()?))
    };
    let out_id = id(output);
    let out_full = full(output);
    for input in inputs {
        let same = match out_id {
            Some(out) => id(input) == Some(out),
            None => out_full.is_some() && std::fs::canonicalize(input).ok() == out_full,
        };
        if same {
            return Err(format!(
                "{}: the output is the same file as the input {}; refusing to overwrite it",
                shown_path(output),
                shown_path(input)
            ));
        }
    }
    Ok(())
}

/// On SIGINT, SIGTERM or SIGHUP: remove the partial output, exit 130. The
/// handler runs on its own thread (`ctrlc`), not in signal context, so it
/// may lock and touch the file system.
fn install_signal_handlers() -> Result<(), String> {
    // SAFETY: setting a signal's disposition to SIG_IGN runs no code in
    // signal context and touches no Rust state. With SIGXFSZ ignored, a
    // write past `ulimit -f` fails with EFBIG, which `io_err` reports, and
    // the temporary file is removed like after any other error.
    #[allow(unsafe_code)]
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    ctrlc::set_handler(|| {
        let guard = partial();
        if let Some(temp) = guard.as_ref() {
            let _ = std::fs::remove_file(temp);
        }
        eprintln!("\ninterrupted");
        // Exiting with the lock held: no other thread can create or rename
        // the temporary file from here on.
        std::process::exit(130);
    })
    .map_err(|e| format!("cannot install the interrupt handler: {e}"))
}

fn run(o: &Options) -> Result<(), String> {
    let text = read_scene_text(&o.scene)?;
    let rows = o.rows.clone().unwrap_or(0..o.height);
    let threads = Threads::plan(o, rows.len() as u32);
    for frame in 0..o.frames {
        let clock = if o.frames > 1 {
            frame as f32 / (o.frames - 1) as f32
        } else {
            0.0
        };
        let options = ParseOptions {
            clock,
            strict: o.strict,
            ..o.settings().parse_options()
        };
        let parse_start = Instant::now();
        let mut warnings = Vec::new();
        let (scene, source) =
            parse_file_scene_located(&o.scene, &text, &options, &mut |w| warnings.push(w))?;
        if !o.quiet && frame == 0 {
            for w in &warnings {
                eprintln!("warning: {w}");
            }
        }
        let mut budget = DecodeBudget::new(o.max_image_mib << 20);
        let loaded = load_fields_within(&scene, &source, &mut budget)?;
        let fields: Vec<HeightField<'_>> = build_fields_located(&scene, &loaded, &source)?
            .into_iter()
            .map(|f| f.with_traversal(o.walk))
            .collect();
        let parse_seconds = parse_start.elapsed().as_secs_f64();

        let output = frame_path(&o.output, frame, o.frames);
        refuse_input_as_output(&output, &input_files(&scene, &source))?;
        let (file, temp) = create_partial(&output)?;
        let order = row_order(o, &scene);
        let mut sink = match Sink::create(&output, file, o.width, rows.len() as u32, order) {
            Ok(sink) => sink,
            Err(e) => {
                discard(temp);
                return Err(e);
            }
        };
        let mut progress = Progress::new(o.quiet, rows.len() as u32);
        let trace_start = Instant::now();
        let result = render_rows(
            &scene,
            &source,
            &fields,
            o,
            threads,
            rows.clone(),
            &mut sink,
            &mut progress,
        )
        .and_then(|stats| sink.finish().map(|()| stats));
        let trace_seconds = trace_start.elapsed().as_secs_f64();
        let stats = match result {
            Ok(stats) => stats,
            Err(e) => {
                discard(temp);
                return Err(e);
            }
        };
        publish(temp, &output)?;
        if o.stats {
            eprintln!(
                "stats: width={} height={} rays={} primary={} shadow={} reflected={} cells={} \
                 tri_tests={} hits={} blocks={} resumed={} parse_seconds={:.6} \
                 trace_seconds={:.6} heap_peak_bytes={}",
                o.width,
                rows.len(),
                stats.rays(),
                stats.primary_rays,
                stats.shadow_rays,
                stats.reflected_rays,
                stats.cells,
                stats.triangle_tests,
                stats.hits,
                stats.blocks,
                stats.resumed,
                parse_seconds,
                trace_seconds,
                ALLOC.snapshot().peak_bytes
            );
        }
    }
    Ok(())
}

/// Parses the command line: `--help` and `--version` print and exit 0;
/// a usage error prints clap's message (with a suggestion for a mistyped
/// option) and exits 1, like every other error.
fn options() -> Result<Options, ExitCode> {
    match Options::try_parse() {
        Ok(o) => Ok(o),
        Err(e) => {
            let _ = e.print();
            Err(if e.use_stderr() {
                ExitCode::from(1)
            } else {
                ExitCode::SUCCESS
            })
        }
    }
}

fn main() -> ExitCode {
    let o = match options() {
        Ok(o) => o,
        Err(code) => return code,
    };
    let result = o
        .check()
        .and_then(|()| install_signal_handlers())
        .and_then(|()| run(&o));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}
