//! The `splinegpu` command line: argument parsing, I/O and exit status only.
//! The contract it follows is docs/input-format.md.

use std::io::{self, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use splinegpu::GpuContext;
use splinegpu::geometry::GeometryJob;
use splinegpu::query::{
    ClosestPoints, CurveIndex, Intersection, Pairs, QueryError, RayHit, SurfaceIndex, SurfacePoint,
    intersections,
};
use splinegpu::surface::SurfaceJob;
use splinegpu_cli::document::queries::{Queries, QueryTarget};
use splinegpu_cli::geometry_output::{self, MeshFormat};
use splinegpu_cli::output::{self, OutputError};
use splinegpu_cli::query_output::{self, QueryFormat};
use splinegpu_cli::surface_output::{self, SurfaceFormat};
use splinegpu_cli::{Document, bench, stream};

/// Evaluate cubic splines in bulk on the GPU (or the f64 CPU reference).
#[derive(Parser)]
#[command(name = "splinegpu", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Tessellate the curves or surfaces of a JSON document into CSV, JSON or NPZ samples, or
    /// surfaces and curves with "geometry" (strokes, tubes, ribbons) into meshes (every
    /// format, .glb and .obj included).
    Tessellate(Io),
    /// Answer a document's "queries": the closest points of its curves or surfaces to many
    /// points, every intersection of its 2-D curves, or the first hits of rays on its 3-D
    /// surfaces, certified, on every CPU thread in float64 (auto and cpu; gpu exits 1, not
    /// supported yet). Answers come in CSV, JSON or NPZ.
    Query(Io),
    /// Run the named benchmark workloads.
    ///
    /// Workloads: w1, w1-b, w1-d (10,000 3-D curves, 9.93 M samples: Catmull-Rom, B-spline,
    /// Catmull-Rom with two derivatives), w1-nurbs (w1's points as clamped NURBS on uneven
    /// knots with weights in [0.5, 2], 32 samples per span), w1-arc (w1's curves at 993 points by arc length),
    /// w1-tol (w1's curves at 1e-3 of their extent), fit-1m, eval-at, cli-w1 (w1's document
    /// through tessellate into a temporary file), w1-x10 (100,000 curves made as w1's, for
    /// GPUs), s1 (1,000 bicubic bspline surfaces of 20 x 20 points, per_segment 8, normals:
    /// 18.8 M vertices) and teapot (1,000 Utah teapots within 1e-3 of their extent, normals),
    /// tubes (10,000 closed 3-D loops, 8 sides, 16 rings a segment: 20.5 M vertices) and
    /// strokes (10,000 open 2-D curves, round joins and caps, tolerance 1e-4 of the extent; its
    /// paths carry "max_error", the mesh's largest distance from the exact stroke), and q1 (the
    /// closest points of 100,000 points on 100 open 2-D Catmull-Rom curves of 16 points).
    /// Paths: memset, gpu-first-call, gpu-device, gpu-end-to-end, cpu-1t, cpu-all, fit,
    /// plain-loop (on w1, w1-nurbs, w1-b, w1-x10, eval-at, fit-1m, s1 and teapot: a plain loop
    /// over the same work; the surfaces' from the control points with basis weights, into the
    /// memory cpu-all f32 fills); the surfaces' cpu-call (the whole call into new memory, every
    /// plane of the output: (u, v), positions, normals, triangles); tubes' and strokes' cpu-all
    /// (the planned job's meshes into new memory, f64), cpu-into (into kept f32 buffers),
    /// cpu-refit (their vertices alone) and cpu-call (planned and made); strokes' cpu-call-1t (planned and made on one thread) and
    /// lyon (lyon's stroke tessellator on the same curves as cubic Beziers at the same width,
    /// joins, caps and tolerance, one thread);
    /// on w1 and w1-x10 gpu-memset (a store-only kernel writing the output's bytes, one vec4 per
    /// invocation) and gpu-store-ceiling (the same in runs of 192 vec4s, the looping shape);
    /// w1's, w1-arc's and w1-tol's cpu-whole (from the points: fitted and planned on every
    /// thread, evaluated in f64 with t into reused memory, the whole library call);
    /// q1's cpu-1t and cpu-all (the whole call: fitted, indexed, answered into new arrays),
    /// gpu-device (the kernel's dispatches) and gpu-end-to-end (the whole call to f32 answers, with
    /// "misses": answers beyond the contract's GPU bound),
    /// plain-loop (the same exact solve on every segment, no index) and kurbo (its nearest on
    /// every segment to 1e-9, with "misses" against the certified answers), the last two on
    /// the first 1,000 points, scaled to all;
    /// w1-tol's "wang" (Wang's count for the same curves; its time is the time to count),
    /// w1-arc's and w1-tol's kurbo anchors; cli-w1's csv-cpu, csv-gpu, npz-cpu, npz-gpu,
    /// floor-cpu (parse, fit and evaluate into reused memory plus a memset of the NPZ file's
    /// size), and csv-write-floor and npz-write-floor (the same, then the CSV or NPZ file's
    /// bytes written whole through the same temporary file and rename).
    Bench {
        /// A workload to run (may repeat; default: all).
        #[arg(long = "workload")]
        workloads: Vec<String>,
        /// One JSON object per line per measurement.
        #[arg(long)]
        json: bool,
    },
    /// Print the adapters wgpu finds and what `--backend auto` would pick.
    Info,
}

/// The input, output and backend of `tessellate` and `query`.
#[derive(Args)]
struct Io {
    /// The input document, or `-` for standard input.
    input: String,
    /// Where to write; standard output when absent or `-`.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Output format; by default the extension of OUTPUT (.csv, .json, .npz, .glb, .obj),
    /// else csv. glb and obj are meshes of a surface document or of curves with geometry.
    #[arg(long)]
    format: Option<Format>,
    /// Evaluator: a hardware GPU when there is one, else the CPU (auto); any adapter wgpu
    /// finds, lavapipe included (gpu, float32); the host reference (cpu, float64).
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    backend: Backend,
}

impl Io {
    /// The output path, `-` meaning standard output (as INPUT's `-` is standard input).
    fn output(&self) -> Option<&Path> {
        self.output
            .as_deref()
            .filter(|path| path.as_os_str() != "-")
    }
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Format {
    Csv,
    Json,
    Npz,
    Glb,
    Obj,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Backend {
    Auto,
    Gpu,
    Cpu,
}

/// A failure and its exit status: 2 for bad input or usage, 1 for everything else.
struct Failure {
    status: u8,
    message: String,
}

impl Failure {
    fn input(message: impl ToString) -> Self {
        Self {
            status: 2,
            message: message.to_string(),
        }
    }

    fn other(message: impl ToString) -> Self {
        Self {
            status: 1,
            message: message.to_string(),
        }
    }
}

fn main() -> ExitCode {
    // Mesa's device-select Vulkan layer prints XDG_RUNTIME_DIR warnings on headless machines
    // unless NODEVICE_SELECT is set before the Vulkan instance exists.
    #[allow(
        unsafe_code,
        reason = "set_var is unsafe from edition 2024; no other thread exists yet"
    )]
    // SAFETY: this is the first statement of main, before any thread is spawned.
    unsafe {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
    remove_temporary_output_on_signals();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Tessellate(io) => tessellate(&io.input, io.output(), io.format, io.backend),
        Command::Query(io) => query(&io.input, io.output(), io.format, io.backend),
        Command::Bench { workloads, json } => bench(&workloads, json),
        Command::Info => info(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("splinegpu: {}", failure.message);
            ExitCode::from(failure.status)
        }
    }
}

/// On SIGINT, SIGTERM or SIGHUP: remove the temporary output file (if one is being written)
/// and exit with 128 + the signal's number, as a shell reports a process killed by it.
fn remove_temporary_output_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    // Without the handler the signal still ends the process; only the temporary file could
    // be left behind, so failing to install it is not worth failing the run.
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            output::remove_pending_outputs();
            std::process::exit(128 + signal);
        }
    });
}

fn tessellate(
    input: &str,
    output: Option<&Path>,
    format: Option<Format>,
    backend: Backend,
) -> Result<(), Failure> {
    let format = format.unwrap_or_else(|| format_of(output));
    let job = match read_document(input)? {
        Document::Curves(job) => job,
        Document::Surfaces(job) => return tessellate_surfaces(&job, output, format, backend),
        Document::Geometry(job) => {
            return tessellate_geometry(&job, output, format, backend);
        }
        Document::Query(_) => {
            return Err(Failure::input(
                "document: \"queries\" are answered by `splinegpu query`, not tessellated",
            ));
        }
    };
    if matches!(format, Format::Glb | Format::Obj) {
        return Err(Failure::input(
            "document: \"curves\" without \"geometry\" make no mesh: .glb and .obj are \
             written for \"surfaces\" or curves with \"geometry\" (use csv, json or npz)",
        ));
    }
    if format == Format::Npz {
        let dim = job.table(0).dim();
        if let Some(c) = (0..job.len()).find(|&c| job.table(c).dim() != dim) {
            let e = OutputError::MixedDimensions {
                curve: c,
                dim: job.table(c).dim(),
                first: dim,
            };
            return Err(Failure::input(e));
        }
    }
    let context = choose_backend(backend)?;
    let format = match format {
        Format::Csv => stream::Format::Csv,
        Format::Json => stream::Format::Json,
        Format::Npz => stream::Format::Npz,
        Format::Glb | Format::Obj => unreachable!("refused above"),
    };
    // Chunks bound the memory a job holds; SPLINEGPU_CHUNK_SAMPLES overrides their size.
    let chunk = std::env::var("SPLINEGPU_CHUNK_SAMPLES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(stream::CHUNK_SAMPLES);
    // A progress bar on stderr, only when it is a terminal.
    let bar = if io::stderr().is_terminal() {
        indicatif::ProgressBar::new(job.sample_count() as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    let mut progress = |n: u64| bar.inc(n);
    let mut emit = |out: &mut dyn Write| -> Result<(), OutputError> {
        let mut out = out;
        stream::write_on(
            &job,
            format,
            chunk,
            context.as_ref(),
            &mut out,
            &mut progress,
        )
    };
    let result = match output {
        None => {
            let mut out = io::BufWriter::new(io::stdout().lock());
            emit(&mut out).and_then(|()| Ok(out.flush()?))
        }
        Some(path) => output::write_output(path, |out| emit(out)),
    };
    bar.finish_and_clear();
    finish(result, output)
}

/// What a query document's answers are.
enum Answers {
    Closest(ClosestPoints),
    /// Closest points on curves from the GPU, in f32.
    ClosestGpu(ClosestPoints<f32>),
    Intersections(Vec<Intersection>),
    /// Closest points on surfaces of D coordinates.
    SurfaceClosest(Vec<SurfacePoint>, usize),
    Rays(Vec<Option<RayHit>>),
}

/// A query document answered and written: closest points and rays on the backend (f32 numbers
/// from the GPU), intersections refined and reported in f64 on the host whatever the backend.
fn query(
    input: &str,
    output: Option<&Path>,
    format: Option<Format>,
    backend: Backend,
) -> Result<(), Failure> {
    let format = match format.unwrap_or_else(|| format_of(output)) {
        Format::Csv => QueryFormat::Csv,
        Format::Json => QueryFormat::Json,
        Format::Npz => QueryFormat::Npz,
        Format::Glb | Format::Obj => {
            return Err(Failure::input(
                "queries are answered as csv, json or npz, not as a mesh (.glb, .obj)",
            ));
        }
    };
    let document = match read_document(input)? {
        Document::Query(document) => document,
        _ => {
            return Err(Failure::input(
                "document: \"queries\" is missing: `splinegpu query` answers a document's \
                 queries (closest, intersections or rays)",
            ));
        }
    };
    // Intersections are refined and reported in f64 on the host whatever the backend (the
    // contract's reading); the rest run on the backend.
    let context = match &document.queries {
        Queries::Intersections(_) => None,
        _ => choose_backend(backend)?,
    };
    let on_device = |e: QueryError| match e {
        QueryError::Input(e) => Failure::input(e.in_document()),
        QueryError::Gpu(e) => Failure::other(e),
    };
    let located = |e: splinegpu::InputError| Failure::input(e.in_document());
    let answers = match (&document.target, &document.queries) {
        (QueryTarget::Curves(tables), Queries::Closest(points)) => {
            let index = CurveIndex::new(tables).map_err(Failure::input)?;
            match &context {
                Some(gpu) => {
                    Answers::ClosestGpu(gpu.closest_points(&index, points).map_err(on_device)?)
                }
                None => Answers::Closest(index.closest_many(points).map_err(located)?),
            }
        }
        (QueryTarget::Curves(tables), Queries::Intersections(listed)) => {
            let pairs = listed.as_deref().map_or(Pairs::All, Pairs::Listed);
            Answers::Intersections(intersections(tables, pairs).map_err(located)?)
        }
        (QueryTarget::Surfaces(tables), Queries::Closest(points)) => {
            let index = SurfaceIndex::new(tables).map_err(Failure::input)?;
            let dim = index.dim();
            let found = match &context {
                Some(gpu) => gpu.closest_on_surfaces(&index, points).map_err(on_device)?,
                None => index.closest_many(points).map_err(located)?,
            };
            Answers::SurfaceClosest(found, dim)
        }
        (QueryTarget::Surfaces(tables), Queries::Rays(rays)) => {
            let index = SurfaceIndex::new(tables).map_err(Failure::input)?;
            Answers::Rays(match &context {
                Some(gpu) => gpu.ray_hits(&index, rays).map_err(on_device)?,
                None => index.rays_many(rays).map_err(located)?,
            })
        }
        _ => unreachable!("the document's checks pair each query with its target"),
    };
    // The GPU's answers are written as f32, whatever the host finished in f64.
    let gpu_numbers = context.is_some();
    let emit = |out: &mut dyn Write| -> Result<(), OutputError> {
        match &answers {
            Answers::Closest(closest) => query_output::write_closest(closest, format, out)?,
            Answers::ClosestGpu(closest) => query_output::write_closest(closest, format, out)?,
            Answers::Intersections(found) => query_output::write_intersections(found, format, out)?,
            Answers::SurfaceClosest(closest, dim) if gpu_numbers => {
                query_output::write_surface_closest::<f32>(closest, *dim, format, out)?;
            }
            Answers::SurfaceClosest(closest, dim) => {
                query_output::write_surface_closest::<f64>(closest, *dim, format, out)?;
            }
            Answers::Rays(hits) if gpu_numbers => {
                query_output::write_rays::<f32>(hits, format, out)?;
            }
            Answers::Rays(hits) => query_output::write_rays::<f64>(hits, format, out)?,
        }
        Ok(())
    };
    let result = match output {
        None => {
            let mut out = io::BufWriter::new(io::stdout().lock());
            emit(&mut out).and_then(|()| Ok(out.flush()?))
        }
        Some(path) => output::write_output(path, |out| emit(out)),
    };
    finish(result, output)
}

/// The run's end after writing `output`: quiet when the reader closed early (`| head`), exit 2
/// for a value that overflows its number type (the input's fault), 1 for the rest.
fn finish(result: Result<(), OutputError>, output: Option<&Path>) -> Result<(), Failure> {
    match (result, output) {
        (Ok(()), _) => Ok(()),
        (Err(OutputError::Io(e)), _) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        (Err(OutputError::Input(e)), _) => Err(Failure::input(e)),
        (
            Err(
                e @ (OutputError::NonFinite { .. }
                | OutputError::SurfaceNonFinite { .. }
                | OutputError::MeshNonFinite { .. }),
            ),
            _,
        ) => Err(Failure::input(e)),
        (Err(OutputError::Io(e)), Some(path)) => Err(Failure::other(format!(
            "cannot write output \"{}\": {e}",
            path.display()
        ))),
        (Err(e), _) => Err(Failure::other(e)),
    }
}

/// A surface document: checked for the format, evaluated on the backend chunk by chunk as it
/// is written.
fn tessellate_surfaces(
    job: &SurfaceJob,
    output: Option<&Path>,
    format: Format,
    backend: Backend,
) -> Result<(), Failure> {
    let format = match format {
        Format::Csv => SurfaceFormat::Csv,
        Format::Json => SurfaceFormat::Json,
        Format::Npz => SurfaceFormat::Npz,
        Format::Glb => SurfaceFormat::Glb,
        Format::Obj => SurfaceFormat::Obj,
    };
    surface_output::check_format(job, format).map_err(Failure::input)?;
    let context = choose_backend(backend)?;
    let result = match &context {
        None => write_surfaces(job, format, output, &mut |chunk| {
            Ok(job.try_evaluate_cpu_chunk(chunk)?)
        }),
        Some(gpu) => write_surfaces(job, format, output, &mut |chunk| {
            Ok(gpu.evaluate_surface_chunk(job, chunk)?)
        }),
    };
    finish(result, output)
}

/// A geometry document: checked for the format, its meshes made on the backend group by group
/// as they are written (the GPU makes tubes and ribbons, dashed or not; strokes are made
/// on the host whatever the backend, rounded to f32 on the GPU's).
fn tessellate_geometry(
    job: &GeometryJob,
    output: Option<&Path>,
    format: Format,
    backend: Backend,
) -> Result<(), Failure> {
    let format = match format {
        Format::Csv => MeshFormat::Csv,
        Format::Json => MeshFormat::Json,
        Format::Npz => MeshFormat::Npz,
        Format::Glb => MeshFormat::Glb,
        Format::Obj => MeshFormat::Obj,
    };
    geometry_output::check_format(job, format).map_err(Failure::input)?;
    let context = choose_backend(backend)?;
    let result = match &context {
        None => write_meshes(job, format, output, &mut |range| {
            Ok(job.try_evaluate_cpu_group(range)?)
        }),
        Some(gpu) => write_meshes(job, format, output, &mut |range| {
            Ok(gpu.evaluate_geometry_group(job, range)?)
        }),
    };
    finish(result, output)
}

/// The job's meshes written as `format` to `output` (standard output when none), each group
/// made by `make`.
fn write_meshes<F: surface_output::Number>(
    job: &GeometryJob,
    format: MeshFormat,
    output: Option<&Path>,
    make: &mut geometry_output::Make<'_, F>,
) -> Result<(), OutputError> {
    let mut emit = |out: &mut dyn Write| geometry_output::write(job, format, out, make);
    match output {
        None => {
            let mut out = io::BufWriter::new(io::stdout().lock());
            emit(&mut out).and_then(|()| Ok(out.flush()?))
        }
        Some(path) => output::write_output(path, emit),
    }
}

/// The job written as `format` to `output` (standard output when none), its surfaces
/// evaluated by `evaluate` chunk by chunk.
fn write_surfaces<F: surface_output::Number>(
    job: &SurfaceJob,
    format: SurfaceFormat,
    output: Option<&Path>,
    evaluate: &mut surface_output::Evaluate<'_, F>,
) -> Result<(), OutputError> {
    let mut emit = |out: &mut dyn Write| surface_output::write(job, format, out, evaluate);
    match output {
        None => {
            let mut out = io::BufWriter::new(io::stdout().lock());
            emit(&mut out).and_then(|()| Ok(out.flush()?))
        }
        Some(path) => output::write_output(path, emit),
    }
}

/// The backend's context: none for the CPU; for auto a hardware GPU's when there is one,
/// saying which on standard error.
fn choose_backend(backend: Backend) -> Result<Option<GpuContext>, Failure> {
    Ok(match backend {
        Backend::Cpu => None,
        Backend::Gpu => Some(GpuContext::new().map_err(Failure::other)?),
        Backend::Auto => match GpuContext::auto().map_err(Failure::other)? {
            Some(context) => {
                let info = context.adapter_info();
                eprintln!(
                    "splinegpu: backend auto: gpu on {} ({:?})",
                    info.name, info.device_type
                );
                Some(context)
            }
            None => {
                eprintln!("splinegpu: backend auto: cpu (no hardware GPU adapter)");
                None
            }
        },
    })
}

/// Reads and parses the input document: a file is parsed as it is read (64 KiB at a time), so
/// its text is never held whole; standard input likewise.
fn read_document(input: &str) -> Result<Document, Failure> {
    let parsed = if input == "-" {
        splinegpu_cli::parse_input_from_reader(io::stdin().lock())
    } else {
        let cannot = |why: &dyn std::fmt::Display| {
            Failure::input(format!("document: cannot read input \"{input}\": {why}"))
        };
        let file = std::fs::File::open(input).map_err(|e| cannot(&e))?;
        if file.metadata().is_ok_and(|m| m.is_dir()) {
            return Err(cannot(&"it is a directory"));
        }
        splinegpu_cli::parse_input_from_reader(file)
    };
    parsed.map_err(Failure::input)
}

fn format_of(output: Option<&Path>) -> Format {
    match output.and_then(Path::extension).and_then(|e| e.to_str()) {
        Some("json") => Format::Json,
        Some("npz") => Format::Npz,
        Some("glb") => Format::Glb,
        Some("obj") => Format::Obj,
        _ => Format::Csv,
    }
}

fn bench(workloads: &[String], json: bool) -> Result<(), Failure> {
    // Check the names before spending minutes on a GPU context and the first workload.
    if let Some(unknown) = workloads
        .iter()
        .find(|w| !bench::WORKLOADS.contains(&w.as_str()))
    {
        return Err(Failure::input(format!(
            "unknown workload \"{unknown}\" (expected one of {})",
            bench::WORKLOADS.join(", ")
        )));
    }
    let start = std::time::Instant::now();
    let gpu = match GpuContext::new() {
        Ok(gpu) => {
            let info = gpu.adapter_info();
            eprintln!(
                "splinegpu: GpuContext::new took {:.1} ms (instance, adapter, device, pipelines)",
                start.elapsed().as_secs_f64() * 1e3
            );
            eprintln!(
                "splinegpu: bench on {} ({:?}; driver {}), {} threads",
                info.name,
                info.device_type,
                info.driver_info,
                splinegpu::available_threads()
            );
            Some(gpu)
        }
        Err(e) => {
            eprintln!("splinegpu: no GPU adapter ({e}); GPU paths skipped");
            None
        }
    };
    let mut memset_gbps = f64::NAN;
    if !json {
        println!(
            "{:<8} {:<17} {:>10} {:>10} {:>10} {:>11} {:>10} {:>8} {:>9}",
            "workload",
            "path",
            "median ms",
            "min ms",
            "max ms",
            "samples",
            "MB",
            "GB/s",
            "% memset"
        );
    }
    bench::run(workloads, gpu.as_ref(), |m| {
        if json {
            println!("{}", m.to_json());
        } else {
            if m.path == "memset" {
                memset_gbps = m.gbps();
            }
            println!(
                "{:<8} {:<17} {:>10.2} {:>10.2} {:>10.2} {:>11} {:>10.1} {:>8.2} {:>9}{}",
                m.workload,
                m.path,
                m.seconds * 1e3,
                m.min_seconds * 1e3,
                m.max_seconds * 1e3,
                m.samples,
                m.bytes as f64 / 1e6,
                m.gbps(),
                if m.path == "memset" {
                    String::new()
                } else {
                    format!("{:.1}", 100.0 * m.gbps() / memset_gbps)
                },
                m.misses
                    .map(|n| format!("  misses {n}"))
                    .or_else(|| m.max_error.map(|e| format!("  max_error {e:.3e}")))
                    .unwrap_or_default()
            );
        }
    })
    .map_err(Failure::other)?;
    Ok(())
}

fn info() -> Result<(), Failure> {
    let instance = splinegpu::new_instance();
    let adapters =
        pollster::block_on(instance.enumerate_adapters(splinegpu::wgpu::Backends::all()));
    if adapters.is_empty() {
        println!("no adapters found (install a Vulkan driver, e.g. mesa-vulkan-drivers)");
    }
    for adapter in &adapters {
        let (info, limits) = (adapter.get_info(), adapter.limits());
        println!("{}", info.name);
        println!("  backend: {:?}", info.backend);
        println!("  device type: {:?}", info.device_type);
        println!("  driver: {} {}", info.driver, info.driver_info);
        println!(
            "  max_storage_buffer_binding_size: {}",
            limits.max_storage_buffer_binding_size
        );
        println!("  max_buffer_size: {}", limits.max_buffer_size);
        println!(
            "  max_compute_workgroups_per_dimension: {}",
            limits.max_compute_workgroups_per_dimension
        );
        println!(
            "  max_compute_invocations_per_workgroup: {}",
            limits.max_compute_invocations_per_workgroup
        );
        println!(
            "  timestamp queries: {}",
            adapter
                .features()
                .contains(splinegpu::wgpu::Features::TIMESTAMP_QUERY)
        );
        let shape = splinegpu::profiling::KernelShape::for_device_type(info.device_type);
        println!(
            "  kernel shape: {} lanes per run of {} samples",
            shape.lanes, shape.run_len
        );
    }
    match splinegpu::hardware_adapter() {
        Some(a) => println!("auto: gpu on {}", a.get_info().name),
        None => println!("auto: cpu (no hardware GPU adapter)"),
    }
    Ok(())
}
