//! `sward bench --quick` runs on the test device and writes results that parse: one summary row
//! per case with finite, positive timings, every frame in the CSV, the Markdown tables and plots.

use std::path::PathBuf;
use std::process::Command;

/// The timed frames of each case in the quick run: enough for a median and a p99, fewer than
/// `--quick`'s ten (the sweep's 28 cases are most of the test's time on a CPU device).
const QUICK_FRAMES: usize = 3;

#[test]
fn quick_bench_runs_and_its_output_parses() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench-quick");
    let _ = std::fs::remove_dir_all(&out);
    let run = Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(["bench", "--quick", "--validation", "--warmup", "1"])
        .args(["--frames", &QUICK_FRAMES.to_string(), "--out", out.to_str().unwrap()])
        .env("RUST_LOG", "error")
        .output()
        .expect("sward runs");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "bench failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        stdout.contains("| blades | none | orientation | frustum | distance | tiles | occlusion | all |"),
        "{stdout}"
    );
    // Every figure printed is measured or said not to be: the copy bandwidth, the sim+cull floor.
    assert!(!stdout.contains("NaN") && !stdout.contains("inf "), "{stdout}");
    assert!(stdout.contains(" GB/s (read + write)"), "{stdout}");

    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut lines = summary.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let rows: Vec<Vec<String>> = lines.map(split_csv).collect();
    assert_eq!(rows.len(), 2 * 2 * 7, "2 presets × 2 counts × 7 culling modes");
    for row in &rows {
        let number = |name: &str| {
            row[column(name)]
                .parse::<f64>()
                .unwrap_or_else(|_| panic!("{name} in {row:?}"))
        };
        for name in [
            "simulate_median_ms",
            "draw_median_ms",
            "gpu_frame_median_ms",
            "cpu_median_ms",
            "cpu_p95_ms",
        ] {
            let v = number(name);
            assert!(v.is_finite() && v > 0.0, "{name} = {v} in {row:?}");
        }
        // Fused with simulate by default, the cull stamp follows the simulate stamp directly.
        let cull = number("cull_median_ms");
        assert!(cull.is_finite() && cull >= 0.0, "cull_median_ms = {cull} in {row:?}");
        // The trample map's pass is a column too: with nothing to trample in these Bezier
        // scenes, two stamps back to back (on lavapipe about half a millisecond apart).
        let trample = number("trample_median_ms");
        let frame = number("gpu_frame_median_ms");
        assert!(
            trample >= 0.0 && trample < 0.1 * frame,
            "trample_median_ms = {trample} of a {frame} ms frame in {row:?}"
        );
        assert!(number("gpu_frame_p95_ms") >= number("gpu_frame_median_ms"));
        assert!(number("gpu_frame_p99_ms") >= number("gpu_frame_p95_ms"));
        // What sward holds on the GPU for the case: a field, its lists and a 320×240 target at
        // least, and not the device's whole memory.
        let memory = number("gpu_memory_mib");
        assert!(memory > 1.0 && memory < 4096.0, "gpu_memory_mib = {memory} in {row:?}");
        assert!(number("cpu_p95_ms") >= number("cpu_median_ms"));
        // The bandwidth floor is a number where the copy probe was resolved, else empty.
        let floor = &row[column("floor_ms")];
        assert!(
            floor.is_empty() || floor.parse::<f64>().is_ok_and(|ms| ms.is_finite() && ms > 0.0),
            "floor_ms = {floor:?} in {row:?}"
        );
        let blades = number("blades");
        let visible = number("visible_median");
        assert!(visible > 0.0 && visible <= blades, "visible {visible} of {blades}");
        if row[column("culling")] == "none" {
            assert_eq!(visible, blades, "with culling off every blade is drawn");
        }
    }
    let frames = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    assert!(
        frames.lines().count() > rows.len() * QUICK_FRAMES,
        "every timed frame has a row"
    );
    let mut setups: Vec<String> = rows
        .iter()
        .map(|r| {
            format!(
                "{}-{}-{}",
                r[column("preset")],
                r[column("route")],
                r[column("quality")]
            )
        })
        .collect();
    setups.dedup();
    assert_eq!(setups.len(), 2, "one setup per preset: {setups:?}");
    for setup in setups {
        for plot in [format!("frame-time-{setup}.png"), format!("passes-{setup}.png")] {
            let image = image::open(out.join(&plot)).unwrap_or_else(|e| panic!("{plot}: {e}"));
            assert!(image.width() > 100 && image.height() > 100);
        }
    }
}

/// Routes and quality presets sweep like any other axis: every row names both, a route that
/// was asked for is the route that ran, and each quality's samples per pixel are recorded.
#[test]
fn bench_sweeps_draw_routes_and_quality_presets() {
    let args = [
        "--quick",
        "--presets",
        "cis565",
        "--modes",
        "all",
        "--counts",
        "2^10",
        "--draw-route",
        "tessellation,strips",
        "--quality",
        "low,high",
    ];
    let (header, rows, stdout) = bench("bench-routes", &args, "summary.csv");
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let named: Vec<[&str; 3]> = rows
        .iter()
        .map(|r| [&r[column("quality")], &r[column("route")], &r[column("msaa")]].map(String::as_str))
        .collect();
    let expected = [
        ["low", "tessellation", "1"],
        ["low", "strips", "1"],
        ["high", "tessellation", "4"],
        ["high", "strips", "4"],
    ];
    assert_eq!(named, expected);
    assert!(stdout.contains("### cis565 · strips · low (1× MSAA)"), "{stdout}");
}

/// Run `sward bench --validation ARGS --out DIR` (DIR named `name` under the test folder) and
/// return the header and rows of its `csv` file (summary.csv or floor.csv) and its stdout.
fn bench(name: &str, args: &[&str], csv: &str) -> (Vec<String>, Vec<Vec<String>>, String) {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&out);
    let run = Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(["bench", "--validation"])
        .args(args)
        .args(["--out", out.to_str().unwrap()])
        .env("RUST_LOG", "error")
        .output()
        .expect("sward runs");
    assert!(
        run.status.success(),
        "bench failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(out.join(csv)).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines.map(split_csv).collect();
    (header, rows, String::from_utf8_lossy(&run.stdout).into_owned())
}

/// Split one CSV line, honouring double quotes.
fn split_csv(line: &str) -> Vec<String> {
    let mut fields = vec![String::new()];
    let mut quoted = false;
    for ch in line.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => fields.push(String::new()),
            c => fields.last_mut().unwrap().push(c),
        }
    }
    fields
}

/// The generated techniques bench too: a count sets the density within the cut-off radius, and
/// the visible count is what the generator kept (billboards for billboards, blades for instanced).
#[test]
fn generated_techniques_bench_with_visible_counts_below_the_candidates() {
    for technique in ["instanced", "billboard"] {
        let args = [
            "--quick",
            "--technique",
            technique,
            "--presets",
            "meadow",
            "--modes",
            "all",
            "--counts",
            "2^14",
        ];
        let (header, rows, _) = bench(&format!("bench-{technique}"), &args, "summary.csv");
        let row = rows.first().expect("one case");
        let value = |name: &str| {
            row[header.iter().position(|h| h == name).unwrap()]
                .parse::<f64>()
                .unwrap()
        };
        let visible = value("visible_median");
        // The view holds a share of the disk: some, not all, of the candidates.
        assert!(
            visible > 200.0 && visible < 16384.0 * 0.5,
            "{technique}: {visible} visible"
        );
        assert!(value("gpu_frame_median_ms") > 0.0);
    }
}

/// `--floor` measures what the device does per second along every way to the screen: blades and
/// triangles of each hardware route, blades of the compute rasterizer, fragments at one sample
/// and at every other count the device has — each a finite, positive rate in floor.csv.
#[test]
fn floor_measures_every_route_and_sample_count() {
    let args = [
        "--floor",
        "--width",
        "96",
        "--height",
        "64",
        "--warmup",
        "1",
        "--frames",
        "3",
        "--max-seconds",
        "1",
    ];
    let (_, rows, stdout) = bench("bench-floor", &args, "floor.csv");
    let has = |kind: &str, route: &str, samples: &str, unit: &str| {
        rows.iter()
            .any(|r| r[1] == kind && r[2] == route && r[3] == samples && r[6] == unit)
    };
    for route in ["tessellation", "strips"] {
        assert!(
            has("geometry", route, "1", "blades/s"),
            "{route} geometry missing: {rows:?}"
        );
        assert!(
            has("geometry", route, "1", "triangles/s"),
            "{route} triangles missing: {rows:?}"
        );
    }
    assert!(
        has("compute", "compute", "1", "blades/s"),
        "compute rate missing: {rows:?}"
    );
    assert!(
        has("fragments", "tessellation", "1", "fragments/s"),
        "1× fragments missing: {rows:?}"
    );
    // Each rate is a finite, positive number, or — where the device's timestamps could not
    // resolve the time — left empty and said to be not measured; never NaN or infinity.
    for r in &rows {
        assert!(
            r[5].is_empty() || r[5].parse::<f64>().is_ok_and(|rate| rate.is_finite() && rate > 0.0),
            "{r:?}"
        );
    }
    let measured = rows.iter().filter(|r| !r[5].is_empty()).count();
    assert!(
        measured >= rows.len() - 1,
        "at most the compute rate is unresolved: {rows:?}"
    );
    assert!(stdout.contains("### Raster floor"), "{stdout}");
    for absurd in ["NaN", "inf "] {
        assert!(!stdout.contains(absurd), "{absurd} in the floor: {stdout}");
    }
    let memory = stdout
        .lines()
        .find(|l| l.starts_with("| memory |"))
        .expect("the memory row");
    assert!(
        memory.contains("bytes/s") && !memory.contains("not measured"),
        "the copy probe is resolved on this device: {memory}"
    );
}

/// `--compare OLD NEW` reads two result folders, prints each case's ratio and fails in one
/// sentence naming the case that got more than the tolerance slower; within it, it passes.
#[test]
fn compare_names_the_case_that_got_slower() {
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench-compare");
    let summary = |frames: &[(&str, f64)]| {
        let mut text = String::from(
            "device,driver,width,height,commit,case,preset,technique,route,quality,msaa,blades,culling,speed,frames,gpu_frame_median_ms,gpu_frame_p99_ms,gpu_memory_mib\n",
        );
        for (case, ms) in frames {
            text.push_str(&format!(
                "\"GPU\",\"driver\",1920,1080,abc,\"{case}\",meadow,instanced,compute,high,4,1024,all,0,60,{ms},{},300\n",
                ms * 1.05
            ));
        }
        text
    };
    for (dir, frames) in [
        ("old", [("instanced 2^26", 18.0), ("prairie 2^24", 9.0)]),
        ("new", [("instanced 2^26", 17.5), ("prairie 2^24", 9.5)]),
    ] {
        std::fs::create_dir_all(root.join(dir)).unwrap();
        std::fs::write(root.join(dir).join("summary.csv"), summary(&frames)).unwrap();
    }
    let compare = |tolerance: &str| {
        Command::new(env!("CARGO_BIN_EXE_sward"))
            .args(["bench", "--compare"])
            .args([root.join("old"), root.join("new")])
            .args(["--tolerance", tolerance])
            .output()
            .expect("sward runs")
    };
    let slower = compare("3");
    let stdout = String::from_utf8_lossy(&slower.stdout);
    let stderr = String::from_utf8_lossy(&slower.stderr);
    assert!(!slower.status.success(), "a case 5.6 % slower passed: {stdout}");
    assert!(stdout.contains("| prairie 2^24 | 9.000 | 9.500 | 1.056 |"), "{stdout}");
    assert!(
        stdout.contains("| instanced 2^26 | 18.000 | 17.500 | 0.972 |"),
        "{stdout}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "one sentence: {stderr}");
    assert!(
        stderr.contains("1 of 2 cases") && stderr.contains("prairie 2^24"),
        "{stderr}"
    );
    assert!(!stderr.contains("instanced"), "the faster case is not named: {stderr}");
    let within = compare("6");
    assert!(within.status.success(), "{}", String::from_utf8_lossy(&within.stderr));
    // Runs made on two devices are not compared.
    let elsewhere = root.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let text = summary(&[("instanced 2^26", 18.0)]).replace("\"GPU\"", "\"Another GPU\"");
    std::fs::write(elsewhere.join("summary.csv"), text).unwrap();
    let across = Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(["bench", "--compare"])
        .args([root.join("old"), elsewhere])
        .output()
        .expect("sward runs");
    let stderr = String::from_utf8_lossy(&across.stderr);
    assert!(!across.status.success() && stderr.contains("one device"), "{stderr}");
}

/// The GPU memory one small meadow case reports (`gpu_memory_mib` of its one row), drawn by
/// `renderer` at `width` × `height`.
fn memory_mib(renderer: &str, [width, height]: [u32; 2]) -> f64 {
    let (width, height) = (width.to_string(), height.to_string());
    let case = "--presets meadow --counts 2^10 --modes all --quality high --warmup 1 --frames 2";
    let mut args: Vec<&str> = case.split(' ').collect();
    args.extend(["--renderer", renderer, "--width", &width, "--height", &height]);
    let name = format!("bench-memory-{renderer}-{width}");
    let (header, rows, _) = bench(&name, &args, "summary.csv");
    let column = header
        .iter()
        .position(|h| h == "gpu_memory_mib")
        .expect("a memory column");
    assert_eq!(rows.len(), 1, "one case");
    let total: f64 = rows[0][column]
        .parse()
        .unwrap_or_else(|_| panic!("gpu_memory_mib in {:?}", rows[0]));
    // Where it goes (memory.csv): named allocations, largest first, within the total.
    let csv = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name).join("memory.csv");
    let text = std::fs::read_to_string(&csv).unwrap_or_else(|e| panic!("{}: {e}", csv.display()));
    let sizes: Vec<f64> = text.lines().skip(1).map(|l| split_csv(l)[6].parse().unwrap()).collect();
    assert!(
        !sizes.is_empty() && sizes.is_sorted_by(|a, b| a >= b),
        "{renderer}: {text}"
    );
    assert!(
        sizes.iter().sum::<f64>() <= total + 0.5,
        "{renderer}: {text} of {total} MiB"
    );
    total
}

/// Both renderers count GPU memory alike, as what the allocator holds (buffers and images): a
/// larger target adds at least its 4× multisampled colour and depth to either one's figure.
#[test]
fn both_renderers_count_the_target_in_their_gpu_memory() {
    let (small, large) = ([320, 240], [640, 480]);
    // Colour and depth, four bytes each, at four samples a pixel: the images that grow.
    let grown = |[w, h]: [u32; 2]| 2.0 * 4.0 * 4.0 * (w * h) as f64 / (1 << 20) as f64;
    let target = grown(large) - grown(small);
    for renderer in ["vulkan", "wgpu"] {
        let [before, after] = [small, large].map(|size| memory_mib(renderer, size));
        assert!(
            after - before >= 0.95 * target,
            "{renderer}: {before:.1} MiB at 320×240, {after:.1} at 640×480; the target alone grows {target:.1}"
        );
    }
}
