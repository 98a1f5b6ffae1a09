//! `render`: a POV-Ray-style scene file to an image, streamed row by row.
//!
//! ```text
//! cargo run --release --example render -- SCENE.pov -o OUT.tga
//!     [--width W] [--height H] [--aa N] [--threads N] [--rows A..B]
//!     [--frames N] [--aov depth] [--stats] [--strict] [--quiet]
//!     [--walk flat|blocks|hierarchy] [--coherence on|off]
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
//! queue. The file is written under a temporary name (`.NAME.partial-PID`
//! in the output's folder) and renamed when complete, so an error or an
//! interrupt never leaves a partial image under the requested name, and an
//! existing file of that name stays as it was until the new one replaces it.
//!
//! Errors print `error: FILE:LINE:COL: message` (or `error: message`) and
//! exit with status 1. An interrupt (Ctrl-C / SIGINT, SIGTERM, SIGHUP)
//! removes the temporary file, prints `interrupted` and exits with status 130.

#[path = "harness/mod.rs"]
mod harness;

use std::io::{IsTerminal, Write};
use std::ops::{ControlFlow, Range};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::{mpsc, Mutex, MutexGuard};
use std::time::Instant;

use harness::alloc_count::CountingAlloc;
use harness::pfm::PfmWriter;
use harness::png_out::PngWriter;
use harness::scene_io::{build_fields, load_fields, parse_file_scene, read_scene_text, FileScene};
use harness::tga::TgaWriter;
use hfray::pixel::Rgb888;
use hfray::render::{render_coherent, render_depth_coherent, RenderSettings, RowOrder, Stats};
use hfray::scene::ParseOptions;
use hfray::{render, render_depth, Camera, ColumnHint, HeightField, Traversal};

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc::new();

const USAGE: &str = "usage: render SCENE.pov -o OUT.(tga|png|pfm) [--width W] [--height H] \
[--aa N] [--threads N] [--rows A..B] [--frames N] [--aov depth] [--stats] [--strict] [--quiet] \
[--walk flat|blocks|hierarchy] [--coherence on|off]";

/// Rows a thread renders before handing the band on.
const BAND_ROWS: u32 = 8;

#[derive(Debug)]
struct Options {
    scene: PathBuf,
    output: PathBuf,
    width: u32,
    height: u32,
    aa: u32,
    threads: u32,
    rows: Option<Range<u32>>,
    frames: u32,
    depth_aov: bool,
    stats: bool,
    strict: bool,
    quiet: bool,
    walk: Traversal,
    coherence: bool,
}

fn parse_number(flag: &str, value: Option<String>, min: u32, max: u32) -> Result<u32, String> {
    let value = value.ok_or_else(|| format!("{flag} needs a value"))?;
    let n: u32 = value
        .parse()
        .map_err(|_| format!("{flag}: '{value}' is not a whole number"))?;
    if n < min || n > max {
        return Err(format!("{flag}: {n} is outside {min}..={max}"));
    }
    Ok(n)
}

fn parse_rows(value: Option<String>) -> Result<Range<u32>, String> {
    let value = value.ok_or("--rows needs a value like 0..100")?;
    let (a, b) = value
        .split_once("..")
        .ok_or_else(|| format!("--rows: '{value}' is not of the form A..B"))?;
    let a: u32 = a
        .parse()
        .map_err(|_| format!("--rows: '{a}' is not a row"))?;
    let b: u32 = b
        .parse()
        .map_err(|_| format!("--rows: '{b}' is not a row"))?;
    if a >= b {
        return Err(format!("--rows: {a}..{b} is empty"));
    }
    Ok(a..b)
}

fn parse_args() -> Result<Options, String> {
    let mut args = std::env::args().skip(1);
    let mut scene = None;
    let mut output = None;
    let mut o = Options {
        scene: PathBuf::new(),
        output: PathBuf::new(),
        width: 320,
        height: 200,
        aa: 1,
        threads: 1,
        rows: None,
        frames: 1,
        depth_aov: false,
        stats: false,
        strict: false,
        quiet: false,
        walk: Traversal::Hierarchy,
        coherence: true,
    };
    // The largest side: a row of 3-byte pixels per thread stays small, and
    // width × height × aa² fits comfortably in u64 counters.
    const MAX_SIDE: u32 = 1 << 16;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "-o" | "--output" => output = Some(args.next().ok_or("-o needs a file name")?),
            "--width" => o.width = parse_number("--width", args.next(), 1, MAX_SIDE)?,
            "--height" => o.height = parse_number("--height", args.next(), 1, MAX_SIDE)?,
            "--aa" => {
                o.aa = parse_number("--aa", args.next(), 1, hfray::render::MAX_AA)?;
            }
            "--threads" => o.threads = parse_number("--threads", args.next(), 1, 256)?,
            "--rows" => o.rows = Some(parse_rows(args.next())?),
            "--frames" => o.frames = parse_number("--frames", args.next(), 1, 100_000)?,
            "--aov" => match args.next().as_deref() {
                Some("depth") => o.depth_aov = true,
                Some(other) => return Err(format!("--aov: unknown AOV '{other}' (only 'depth')")),
                None => return Err("--aov needs a value ('depth')".into()),
            },
            "--walk" => {
                o.walk = match args.next().as_deref() {
                    Some("flat") => Traversal::Flat,
                    Some("blocks") => Traversal::Blocks,
                    Some("hierarchy") => Traversal::Hierarchy,
                    other => {
                        return Err(format!(
                            "--walk: '{}' is not flat, blocks or hierarchy",
                            other.unwrap_or("")
                        ))
                    }
                }
            }
            "--coherence" => {
                o.coherence = match args.next().as_deref() {
                    Some("on") => true,
                    Some("off") => false,
                    other => {
                        return Err(format!(
                            "--coherence: '{}' is not on or off",
                            other.unwrap_or("")
                        ))
                    }
                }
            }
            "--stats" => o.stats = true,
            "--strict" => o.strict = true,
            "--quiet" => o.quiet = true,
            "-h" | "--help" => return Err(USAGE.into()),
            flag if flag.starts_with('-') => {
                return Err(format!("unknown option '{flag}'\n{USAGE}"))
            }
            path => {
                if scene.replace(PathBuf::from(path)).is_some() {
                    return Err(format!("more than one scene file given\n{USAGE}"));
                }
            }
        }
    }
    o.scene = scene.ok_or_else(|| format!("no scene file given\n{USAGE}"))?;
    o.output = PathBuf::from(output.ok_or_else(|| format!("no output file given (-o)\n{USAGE}"))?);
    if let Some(rows) = &o.rows {
        if rows.end > o.height {
            return Err(format!(
                "--rows {}..{} goes past the image height {}",
                rows.start, rows.end, o.height
            ));
        }
    }
    let ext = extension(&o.output);
    match (ext.as_str(), o.depth_aov) {
        ("tga" | "png", false) | ("pfm", true) => {}
        ("pfm", false) => return Err("a .pfm output holds the depth AOV: add --aov depth".into()),
        (_, true) => return Err("--aov depth writes a .pfm file".into()),
        _ => {
            return Err(format!(
                "{}: unknown output type (use .tga, .png, or .pfm with --aov depth)",
                o.output.display()
            ))
        }
    }
    Ok(o)
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

fn io_err(path: &Path, e: std::io::Error) -> String {
    format!("{}: {e}", path.display())
}

impl Sink {
    /// Creates `temp` for the final `path`, typed by `path`'s extension.
    fn create(
        path: &Path,
        temp: &Path,
        width: u32,
        height: u32,
        order: RowOrder,
    ) -> Result<Sink, String> {
        let err = |e| io_err(path, e);
        let file = std::io::BufWriter::new(std::fs::File::create(temp).map_err(err)?);
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

/// Renders `rows` of the frame on `threads` threads (bands of
/// [`BAND_ROWS`] handed out round-robin), passing rows to `sink` in order.
fn render_rows(
    scene: &FileScene<'_>,
    fields: &[HeightField<'_>],
    o: &Options,
    rows: Range<u32>,
    sink: &mut Sink,
    progress: &mut Progress,
) -> Result<Stats, String> {
    let order = row_order(o, scene);
    let base = RenderSettings::new(o.width, o.height)
        .with_aa(o.aa)
        .with_order(order);
    let threads = o
        .threads
        .min(rows.len().div_ceil(BAND_ROWS as usize) as u32)
        .max(1);
    let mut bands: Vec<Range<u32>> = rows
        .clone()
        .step_by(BAND_ROWS as usize)
        .map(|a| a..(a + BAND_ROWS).min(rows.end))
        .collect();
    if order == RowOrder::BottomUp {
        bands.reverse();
    }
    std::thread::scope(|s| {
        // One bounded queue per worker: a worker runs at most one band
        // ahead of the writer, so memory stays at ~2 bands per thread.
        let mut receivers = Vec::new();
        let mut handles = Vec::new();
        for k in 0..threads as usize {
            let (tx, rx) = mpsc::sync_channel::<Result<Row, String>>(2 * BAND_ROWS as usize);
            receivers.push(rx);
            let my_bands: Vec<Range<u32>> = bands
                .iter()
                .skip(k)
                .step_by(threads as usize)
                .cloned()
                .collect();
            let base = base.clone();
            let depth = o.depth_aov;
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
                            let _ = tx.send(Err(e.to_string()));
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

/// A sibling of `path` to write to before renaming.
fn temp_path(path: &Path) -> PathBuf {
    let name = path.file_name().and_then(|s| s.to_str()).unwrap_or("out");
    path.with_file_name(format!(".{name}.partial-{}", std::process::id()))
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

/// On SIGINT, SIGTERM or SIGHUP: remove the partial output, exit 130. The
/// handler runs on its own thread (`ctrlc`), not in signal context, so it
/// may lock and touch the file system.
fn install_interrupt_handler() -> Result<(), String> {
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

/// Removes the temporary file (after an error).
fn discard(temp: &Path) {
    let mut guard = partial();
    let _ = std::fs::remove_file(temp);
    *guard = None;
}

fn run(o: &Options) -> Result<(), String> {
    let text = read_scene_text(&o.scene)?;
    let rows = o.rows.clone().unwrap_or(0..o.height);
    for frame in 0..o.frames {
        let clock = if o.frames > 1 {
            frame as f32 / (o.frames - 1) as f32
        } else {
            0.0
        };
        let options = ParseOptions {
            image_width: o.width,
            image_height: o.height,
            clock,
            strict: o.strict,
        };
        let parse_start = Instant::now();
        let mut warnings = Vec::new();
        let scene = parse_file_scene(&o.scene, &text, &options, &mut |w| warnings.push(w))?;
        if !o.quiet && frame == 0 {
            for w in &warnings {
                eprintln!("warning: {w}");
            }
        }
        let loaded = load_fields(&scene, &o.scene)?;
        let fields: Vec<HeightField<'_>> = build_fields(&scene, &loaded)?
            .into_iter()
            .map(|f| f.with_traversal(o.walk))
            .collect();
        let parse_seconds = parse_start.elapsed().as_secs_f64();

        let output = frame_path(&o.output, frame, o.frames);
        let temp = temp_path(&output);
        let mut sink = {
            let mut guard = partial();
            *guard = Some(temp.clone());
            match Sink::create(
                &output,
                &temp,
                o.width,
                rows.len() as u32,
                row_order(o, &scene),
            ) {
                Ok(sink) => sink,
                Err(e) => {
                    let _ = std::fs::remove_file(&temp);
                    *guard = None;
                    return Err(e);
                }
            }
        };
        let mut progress = Progress::new(o.quiet, rows.len() as u32);
        let trace_start = Instant::now();
        let result = render_rows(&scene, &fields, o, rows.clone(), &mut sink, &mut progress)
            .and_then(|stats| sink.finish().map(|()| stats));
        let trace_seconds = trace_start.elapsed().as_secs_f64();
        let stats = match result {
            Ok(stats) => stats,
            Err(e) => {
                discard(&temp);
                return Err(e);
            }
        };
        {
            let mut guard = partial();
            let renamed = std::fs::rename(&temp, &output);
            if renamed.is_err() {
                let _ = std::fs::remove_file(&temp);
            }
            *guard = None;
            renamed.map_err(|e| io_err(&output, e))?;
        }
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

fn main() -> ExitCode {
    let result = install_interrupt_handler()
        .and_then(|()| parse_args())
        .and_then(|o| run(&o));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}
