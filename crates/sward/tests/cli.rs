//! The `sward` command as a user meets it: a good render, and one clear sentence with a non-zero
//! exit (never a panic) for every kind of bad input.

use std::path::PathBuf;
use std::process::{Command, Output};

fn sward(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_sward"));
    cmd.args(args).env("RUST_LOG", "off");
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("sward runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli-tests");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Run with a scene file holding `text`; expect failure with one line containing every `needle`.
fn rejects_scene(name: &str, text: &str, needles: &[&str]) {
    let path = scratch(name);
    std::fs::write(&path, text).unwrap();
    let out = sward(
        &[
            "render",
            "--scene",
            path.to_str().unwrap(),
            "--out",
            scratch("never.png").to_str().unwrap(),
        ],
        &[],
    );
    fails_with(&out, needles);
}

fn fails_with(out: &Output, needles: &[&str]) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "should fail; stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "panicked: {stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "not one line: {stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "'{needle}' missing from: {stderr}");
    }
}

/// `render --animation N` writes an animated PNG of N frames that play in a loop at the asked
/// frame rate, the grass moving from frame to frame (the wind and the rolling spheres of the
/// trampling scene), and with `--sequence` each frame as its own PNG, the same pixels.
#[test]
fn renders_an_animation_and_its_frames() {
    let out_path = scratch("animation.png");
    let frame = |k: u32| scratch(&format!("animation-{k:04}.png"));
    for k in 1..=4 {
        let _ = std::fs::remove_file(frame(k));
    }
    let args = [
        "render", "--scene", "trample", "--width", "64", "--height", "48", "--steps", "30",
    ];
    let animation = [
        "--animation",
        "4",
        "--fps",
        "12",
        "--sequence",
        "--orbit",
        "30",
        "--validation",
    ];
    let out = sward(
        &[&args[..], &animation, &["--out", out_path.to_str().unwrap()]].concat(),
        &[],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("4 frames at 12 fps after 30 steps"));

    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out_path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let control = reader.info().animation_control.expect("an animated PNG");
    assert_eq!((control.num_frames, control.num_plays), (4, 0));
    let mut frames = Vec::new();
    for k in 1..=4 {
        let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
        reader.next_frame(&mut rgb).unwrap();
        let delay = reader.info().frame_control.unwrap();
        assert_eq!((delay.delay_num, delay.delay_den), (1, 12));
        let still = image::open(frame(k)).expect("the sequence's frame").to_rgb8();
        assert_eq!(still.as_raw(), &rgb, "frame {k} of the sequence is the animation's");
        frames.push(rgb);
    }
    for pair in frames.windows(2) {
        let moved = pair[0].iter().zip(&pair[1]).filter(|(a, b)| a != b).count();
        assert!(
            moved > pair[0].len() / 20,
            "the grass hardly moved between frames: {moved} bytes"
        );
    }
}

#[test]
fn renders_a_png_with_validation_on() {
    let out_path = scratch("small.png");
    let _ = std::fs::remove_file(&out_path);
    let out = sward(
        &[
            "render",
            "--width",
            "96",
            "--height",
            "64",
            "--steps",
            "4",
            "--validation",
            "--out",
            out_path.to_str().unwrap(),
        ],
        &[],
    );
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let image = image::open(&out_path).unwrap().to_rgba8();
    assert_eq!(image.dimensions(), (96, 64));
}

/// `render --shaders DIR` draws with the shaders in DIR compiled now (the bench's `--shaders`: the
/// tessellation and mesh GLSL, and the core's WESL modules it holds in place of the built-in
/// ones): the folder as shipped draws the built-in picture, a folder whose blades are shaded red
/// draws a redder one, on either renderer; a folder that is not there is refused in one sentence.
#[test]
fn render_draws_with_the_shaders_of_a_folder() {
    let shipped = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../sward-gpu/shaders");
    let red = scratch("red-shaders");
    let _ = std::fs::remove_dir_all(&red);
    std::fs::create_dir_all(&red).unwrap();
    for entry in std::fs::read_dir(&shipped).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, red.join(path.file_name().unwrap())).unwrap();
    }
    // The drawn blades are shaded by the core's WGSL: its module in the folder replaces the
    // built-in one.
    let (_, wgsl) = sward_wgpu::portable::MODULES
        .iter()
        .find(|(name, _)| *name == "shading")
        .expect("the core has a shading module");
    let wgsl_albedo = "let albedo = blade_albedo(uv.y, look, vary);";
    assert!(
        wgsl.contains(wgsl_albedo),
        "shading.wesl no longer finds the blade's albedo so"
    );
    std::fs::write(
        red.join("shading.wesl"),
        wgsl.replace(wgsl_albedo, "let albedo = vec3<f32>(1.0, 0.0, 0.0);"),
    )
    .unwrap();
    let picture = |name: &str, shaders: Option<&PathBuf>, renderer: &str| {
        let png = scratch(name);
        let mut args = vec![
            "render",
            "--renderer",
            renderer,
            "--width",
            "96",
            "--height",
            "64",
            "--steps",
            "2",
            "--out",
            png.to_str().unwrap(),
        ];
        if let Some(dir) = shaders {
            args.extend(["--shaders", dir.to_str().unwrap()]);
        }
        let out = sward(&args, &[]);
        assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
        image::open(&png).unwrap().to_rgb8()
    };
    let redness = |image: &image::RgbImage| image.pixels().map(|p| p[0] as f64 - p[1] as f64).sum::<f64>();
    // Either renderer: the portable one takes the folder's WESL modules, the Vulkan one its
    // GLSL too.
    for renderer in ["vulkan", "wgpu"] {
        let built_in = picture(&format!("shaders-built-in-{renderer}.png"), None, renderer);
        assert_eq!(
            picture(&format!("shaders-shipped-{renderer}.png"), Some(&shipped), renderer),
            built_in,
            "the shipped folder drew another picture ({renderer})"
        );
        let reddened = picture(&format!("shaders-red-{renderer}.png"), Some(&red), renderer);
        assert!(
            redness(&reddened) > redness(&built_in) + 1000.0,
            "blades shaded red drew no redder picture ({renderer}): {} against {}",
            redness(&reddened),
            redness(&built_in)
        );
    }
    let missing = scratch("no-such-shaders");
    fails_with(
        &sward(
            &[
                "render",
                "--shaders",
                missing.to_str().unwrap(),
                "--out",
                scratch("never.png").to_str().unwrap(),
            ],
            &[],
        ),
        &["no-such-shaders"],
    );
    fails_with(
        &sward(
            &[
                "render",
                "--renderer",
                "wgpu",
                "--shaders",
                missing.to_str().unwrap(),
                "--out",
                scratch("never.png").to_str().unwrap(),
            ],
            &[],
        ),
        &["--shaders", "no-such-shaders", "not a folder"],
    );
}

/// `sward soak` runs the trampling scene at extreme parameters (a small field, a short run, with
/// the validation layer) and reports it sound — with its blades bent well away from rest, so the
/// run did what a soak is for; a bad step count is refused, naming the flag.
/// `sward soak` walking a streamed field: the camera goes 100 units along a path (tiles made
/// anew all the way), the blades physics steps stay sound, and the GPU memory in use stays flat
/// (the run fails otherwise).
#[test]
fn soak_walks_a_streamed_field_with_memory_flat() {
    let out = sward(
        &[
            "--validation",
            "soak",
            "--scene",
            "trail",
            "--set",
            "field.blades=16384",
            "--set",
            "instanced.density=20",
            "--set",
            "instanced.inner_radius=6",
            "--set",
            "camera.position=[0.0,1.7,0.0]",
            "--set",
            "camera_path.points=[[0.0,1.7,0.0],[200.0,1.7,0.0]]",
            "--speed",
            "50",
            "--steps",
            "240",
            "--check-every",
            "80",
        ],
        &[],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("the camera walked 100 units"), "{stdout}");
    assert!(stdout.contains("GPU memory in use flat"), "{stdout}");
    let stepped: usize = stdout
        .split("at least ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(stepped > 100, "too few blades checked free of their twins: {stdout}");
}

#[test]
fn soak_checks_a_long_simulation_and_reports_it_sound() {
    let out = sward(
        &[
            "--validation",
            "soak",
            "--scene",
            "trample",
            "--set",
            "field.blades=2000",
            "--steps",
            "2400",
            "--check-every",
            "800",
            "--extreme",
        ],
        &[],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    assert!(
        stdout.contains("2400 steps of trample (2000 blades, extreme parameters)"),
        "{stdout}"
    );
    let moved: f32 = stdout
        .split("tips moved up to ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(0.0);
    assert!(
        moved > 0.3,
        "the blades hardly moved ({moved} of their height): {stdout}"
    );
    let bad = sward(&["soak", "--steps", "0"], &[]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("'0' for '--steps"));
}

#[test]
fn missing_scene_file() {
    let out = sward(&["render", "--scene", "/nonexistent/field.toml"], &[]);
    fails_with(&out, &["cannot read scene file /nonexistent/field.toml"]);
}

#[test]
fn unknown_scene_name_lists_the_shipped_ones() {
    fails_with(
        &sward(&["render", "--scene", "savanna"], &[]),
        &["no scene named 'savanna'", "meadow"],
    );
    // A near miss is answered with the nearest shipped name.
    fails_with(
        &sward(&["render", "--scene", "prarie"], &[]),
        &["no scene named 'prarie'", "did you mean prairie?"],
    );
}

/// One meaning per word: `render` without `--out` writes the scene's own name, not the
/// default scene's, into the directory it runs in.
#[test]
fn render_writes_the_scene_s_name_without_out() {
    let dir = scratch("out-default");
    std::fs::create_dir_all(&dir).unwrap();
    let written = dir.join("planet.png");
    let _ = std::fs::remove_file(&written);
    let out = Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(["render", "--scene", "planet", "--set", "field.blades=200"])
        .args(["--steps", "1", "--width", "32", "--height", "24"])
        .current_dir(&dir)
        .env("RUST_LOG", "off")
        .output()
        .expect("sward runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(written.exists(), "render --scene planet wrote no planet.png");
    assert!(
        !dir.join("meadow.png").exists(),
        "render wrote the default scene's name"
    );
}

#[test]
fn malformed_scene_file() {
    rejects_scene("malformed.toml", "[field\nblades = 3\n", &["malformed.toml", "line 1"]);
}

#[test]
fn negative_height() {
    rejects_scene(
        "negative.toml",
        "[field]\nheight = [-1.0, 2.0]\n",
        &["field.height", "0 < min ≤ max"],
    );
}

/// A streamed field: a budget too small for its hand-over names the least that does; a planet
/// cannot stream; a camera speed must be a number of units per second.
#[test]
fn bad_streaming_names_what_is_allowed() {
    let landscape = "technique = \"landscape\"\n[instanced]\ninner_radius = 11.0\n";
    rejects_scene(
        "small-budget.toml",
        &format!("{landscape}[field]\nstream = true\nblades = 5000\n"),
        &["field.blades = 5000", "at least 65536 blades", "hand-over at 11"],
    );
    rejects_scene(
        "streamed-planet.toml",
        &format!("{landscape}[field]\nstream = true\nblades = 65536\n[surface]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 5.0\n"),
        &["field.stream", "plane, terrain or height map"],
    );
    // A flag's error is clap's: one sentence, then its pointer to --help.
    let out = sward(&["bench", "--speeds", "fast"], &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("--speeds") && stderr.contains("units per second"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn zero_blades() {
    rejects_scene("zero.toml", "[field]\nblades = 0\n", &["field.blades = 0", "1 to"]);
}

#[test]
fn blades_wider_than_tall() {
    rejects_scene(
        "wide.toml",
        "[field]\nheight = [0.5, 1.0]\nwidth = [0.2, 0.8]\n",
        &["field.width", "wider than tall"],
    );
}

#[test]
fn unknown_wind_type() {
    rejects_scene(
        "wind.toml",
        "[wind]\ntype = \"hurricane\"\n",
        &["line 2", "hurricane", "waves", "noise"],
    );
}

#[test]
fn bad_flag_values() {
    let out = sward(&["render", "--width", "0"], &[]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--width"));
    // A camera turning by a NaN would put a NaN on the GPU.
    let out = sward(&["render", "--animation", "2", "--orbit", "nan"], &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("--orbit") && stderr.contains("degrees per second"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    // The instanced grass's workgroups must cut a patch's cells evenly.
    let out = sward(&["bench", "--quick", "--instanced-workgroup", "96"], &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success()
            && stderr.contains("--instanced-workgroup")
            && stderr.contains("96 does not divide a patch's 1024 cells"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// The portable renderer's splat-cell flags: asking for the 32-bit cells and leaving them out at
/// once, or either on the Vulkan renderer (which splats into 64-bit cells only), is one sentence
/// and a non-zero exit, before any GPU work.
#[test]
fn splat_cell_flags_that_cannot_apply_are_refused_in_one_sentence() {
    let cases: [(&[&str], &str); 4] = [
        (
            &["--without", "subgroups", "bench", "--quick"],
            "--without subgroups leaves out what only the portable renderer uses",
        ),
        (
            &[
                "--narrow-splats",
                "--without",
                "narrow-splats",
                "render",
                "--renderer",
                "wgpu",
            ],
            "--narrow-splats asks for the 32-bit splat cells that --without narrow-splats leaves out",
        ),
        (
            &["--narrow-splats", "render", "--renderer", "vulkan"],
            "the Vulkan renderer splats into 64-bit cells",
        ),
        (
            &["--without", "narrow-splats", "bench", "--quick"],
            "the Vulkan renderer splats into 64-bit cells",
        ),
    ];
    for (args, needle) in cases {
        let out = sward(args, &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail: {stderr}");
        assert!(
            stderr.contains(needle) && stderr.lines().count() == 1,
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

/// Routes and quality presets: an unknown name lists the allowed ones; a negative hand-over
/// distance of the compute route is one sentence naming the key.
#[test]
fn bad_draw_routes_and_quality_presets_name_what_is_allowed() {
    for (flag, value, allowed) in [
        ("--draw-route", "raytraced", ["tessellation", "strips", "compute"]),
        ("--quality", "cinematic", ["low", "medium", "ultra"]),
    ] {
        let out = sward(&["render", flag, value], &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{flag} {value} should fail");
        assert!(!stderr.contains("panicked"), "{stderr}");
        for name in allowed {
            assert!(stderr.contains(name), "'{name}' missing from: {stderr}");
        }
    }
    let compute_route_values: [(&str, &[&str]); 3] = [
        ("lod.splat_distance=-1", &["lod.splat_distance", "-1"]),
        ("lod.strip_distance=-2", &["lod.strip_distance", "-2"]),
        ("lod.compute_raster=3", &["lod.compute_raster"]),
    ];
    for (set, words) in compute_route_values {
        fails_with(&sward(&["render", "--draw-route", "compute", "--set", set], &[]), words);
    }
}

/// On a device without mesh shaders (withheld by `--without`) asking for the mesh route falls
/// back to the compute route and says so once, in one sentence naming what is missing, for
/// render and bench alike; a device without 64-bit atomics draws the compute route by strips.
#[test]
fn a_route_the_device_lacks_falls_back_and_says_so_once() {
    let out_path = scratch("fallback.png");
    let bench_dir = scratch("fallback-bench");
    let small = ["--width", "64", "--height", "64", "--steps", "2", "--validation"];
    let cases: [(Vec<&str>, &str, &str); 3] = [
        (
            [
                &["--without", "mesh-shaders", "render", "--draw-route", "mesh"][..],
                &["--out", out_path.to_str().unwrap()],
                &small,
            ]
            .concat(),
            "the mesh draw route needs mesh shaders (VK_EXT_mesh_shader), which llvmpipe",
            "compute route",
        ),
        (
            [
                &["--without", "int64-atomics", "render", "--draw-route", "compute"][..],
                &["--out", out_path.to_str().unwrap()],
                &small,
            ]
            .concat(),
            "the compute draw route needs 64-bit buffer atomics (shaderBufferInt64Atomics)",
            "strips route",
        ),
        (
            vec![
                "--without",
                "mesh-shaders",
                "bench",
                "--quick",
                "--validation",
                "--draw-route",
                "mesh,compute",
                "--presets",
                "meadow",
                "--counts",
                "2^10",
                "--modes",
                "all",
                "--warmup",
                "1",
                "--frames",
                "3",
                "--out",
                bench_dir.to_str().unwrap(),
            ],
            "the mesh draw route needs mesh shaders (VK_EXT_mesh_shader)",
            "| compute |",
        ),
    ];
    for (args, said, drawn) in cases {
        let out = sward(&args, &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{args:?} failed: {stderr}");
        let notes: Vec<_> = stderr.lines().filter(|l| l.contains("draw route needs")).collect();
        assert_eq!(notes.len(), 1, "{args:?}: said once, in one line: {stderr}");
        assert!(notes[0].contains(said) && notes[0].ends_with("instead"), "{}", notes[0]);
        assert!(stdout.contains(drawn), "{args:?}: the route drawn is named: {stdout}");
        assert!(!stdout.contains("| mesh |"), "no row claims the mesh route: {stdout}");
    }
}

/// Out of GPU memory (provoked by `--gpu-memory`, a budget below the device's) is one sentence
/// naming the most that fits — and that much does fit: the blade count it names renders and
/// one more does not; the image size it names renders (with a MiB more for a small field) and
/// a larger one does not.
#[test]
fn out_of_gpu_memory_names_the_largest_field_and_image_that_fit() {
    let out_path = scratch("budget.png");
    let render = |budget: &str, blades: &str, size: [u32; 2]| {
        let [w, h] = [size[0].to_string(), size[1].to_string()];
        let blades = format!("field.blades={blades}");
        let args = ["--gpu-memory", budget, "render", "--set", &blades, "--steps", "1"];
        let size = [
            "--width",
            &w,
            "--height",
            &h,
            "--validation",
            "--out",
            out_path.to_str().unwrap(),
        ];
        sward(&[&args[..], &size].concat(), &[])
    };
    let number_after = |text: &str, words: &str| -> String {
        let at = text
            .find(words)
            .unwrap_or_else(|| panic!("'{words}' missing from: {text}"))
            + words.len();
        text[at..]
            .chars()
            .take_while(|c| c.is_ascii_digit() || *c == '×')
            .collect()
    };

    let refused = render("64", "1000000", [160, 120]);
    fails_with(
        &refused,
        &["a field of 1000000 blades needs", "MiB are free on this GPU; at most"],
    );
    let most = number_after(&String::from_utf8_lossy(&refused.stderr), "at most ");
    let most: u64 = most.parse().unwrap();
    assert!(most > 1000, "{most}");
    assert!(
        render("64", &most.to_string(), [160, 120]).status.success(),
        "{most} blades fit"
    );
    fails_with(&render("64", &(most + 1).to_string(), [160, 120]), &["at most"]);

    let refused = render("64", "100", [4000, 3000]);
    fails_with(
        &refused,
        &[
            "a 4000×3000 image needs",
            "the largest image of that shape that fits is",
        ],
    );
    let largest = number_after(&String::from_utf8_lossy(&refused.stderr), "that fits is ");
    let (w, h) = largest.split_once('×').unwrap();
    let [w, h]: [u32; 2] = [w.parse().unwrap(), h.parse().unwrap()];
    assert!(w > 400 && (w as f32 / h as f32 - 4.0 / 3.0).abs() < 0.01, "{w}×{h}");
    let fits = render("66", "100", [w, h]);
    assert!(
        fits.status.success(),
        "{w}×{h} fits: {}",
        String::from_utf8_lossy(&fits.stderr)
    );
    fails_with(
        &render("64", "100", [w + 2, h + 2]),
        &["the largest image of that shape that fits is"],
    );
}

/// A lost device (every submission after the fourth reports one, the hook a test has: a real
/// one cannot be caused on purpose) ends `render` with one sentence and a non-zero exit.
#[test]
fn a_lost_device_ends_in_one_sentence() {
    let out_path = scratch("lost.png");
    let args = ["--lose-device-after", "4", "render", "--width", "64", "--height", "64"];
    fails_with(
        &sward(&[&args[..], &["--out", out_path.to_str().unwrap()]].concat(), &[]),
        &["the GPU was lost while", "sward cannot go on"],
    );
}

/// The route is a scene value too: `[quality] route` picks it, `--draw-route` overrides it, and
/// a name that is not a route is one sentence with the file's line.
#[test]
fn the_scene_file_picks_the_draw_route() {
    let path = scratch("strips.toml");
    std::fs::write(&path, "[field]\nblades = 500\n\n[quality]\nroute = \"strips\"\n").unwrap();
    let out_png = scratch("route.png");
    let render = |route: &[&str]| {
        let scene = [
            "render",
            "--scene",
            path.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "64",
        ];
        let rest = ["--steps", "1", "--out", out_png.to_str().unwrap()];
        let out = sward(&[&scene[..], route, &rest[..]].concat(), &[]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    assert!(render(&[]).contains("strips route"));
    assert!(render(&["--draw-route", "tessellation"]).contains("tessellation route"));
    rejects_scene(
        "bad-route.toml",
        "[quality]\nroute = \"raytraced\"\n",
        &["bad-route.toml", "line 2", "raytraced", "tessellation", "compute"],
    );
}

#[test]
fn no_vulkan_driver() {
    let none = [
        ("VK_DRIVER_FILES", "/nonexistent/icd.json"),
        ("VK_ICD_FILENAMES", "/nonexistent/icd.json"),
    ];
    fails_with(
        &sward(&["info"], &none),
        &["no Vulkan driver was found", "mesa-vulkan-drivers"],
    );
}

/// `sward scene` prints every key of a scene file as a commented scene file, which loads as
/// it stands (the default scene); `--markdown` is the reference page, as
/// docs/scene-reference.md holds it.
#[test]
fn scene_prints_the_reference_as_a_scene_file_and_as_the_docs_page() {
    let out = sward(&["scene"], &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    for key in [
        "blades = 8192",
        "# [[collider]]",
        "# With type = \"terrain\":",
        "allowed: a whole number from 1",
    ] {
        assert!(text.contains(key), "`sward scene` lacks {key}");
    }
    let scene = scratch("reference.toml");
    std::fs::write(&scene, text.as_bytes()).unwrap();
    let loaded = sward_core::Scene::load(&scene).unwrap();
    assert_eq!(loaded.field.blades, sward_core::Scene::default().field.blades);
    let page = sward(&["scene", "--markdown"], &[]);
    assert!(page.status.success());
    let docs = include_str!("../../../docs/scene-reference.md");
    assert_eq!(
        String::from_utf8_lossy(&page.stdout),
        docs,
        "docs/scene-reference.md is stale"
    );
}

/// `info` lists every Vulkan device with the index `--gpu` takes, its driver and the draw
/// routes it allows (the one listed first, where usable, is the one `--gpu 0` opens), then
/// what the portable renderer makes of each wgpu backend's adapter.
#[test]
fn info_lists_every_device_with_its_index_driver_and_routes() {
    let out = sward(&["info"], &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    let listed: Vec<&str> = stdout.lines().filter(|l| l.starts_with("  ")).collect();
    assert!(!listed.is_empty(), "no device listed: {stdout}");
    for (k, line) in listed.iter().enumerate() {
        assert!(line.starts_with(&format!("  {k}: ")), "device {k} not numbered: {line}");
        assert!(line.contains("driver "), "no driver: {line}");
        assert!(
            line.contains("draw routes: ") || line.contains("not usable: lacks "),
            "neither routes nor what it lacks: {line}"
        );
    }
    // Every device draws strips where it is usable at all.
    assert!(listed.iter().any(|l| l.contains("strips")), "{stdout}");
    // Each wgpu backend with an adapter, and what the portable renderer makes of it: here
    // lavapipe (Vulkan) and llvmpipe (GL), which reads no depth texture in compute.
    let adapter = |backend: &str| {
        stdout
            .lines()
            .find(|l| l.starts_with(&format!("wgpu {backend} (")))
            .unwrap_or_else(|| panic!("no wgpu {backend} adapter said: {stdout}"))
    };
    // lavapipe has 64-bit atomic min and max: the far field is splatted there, into 32-bit
    // cells on GL.
    for (backend, far) in [
        (
            "Vulkan",
            "splats the generated grass and billboards beyond their splat distances by compute, as",
        ),
        ("Gl", "beyond their splat distances by compute into 32-bit cells"),
    ] {
        let line = adapter(backend);
        assert!(
            line.contains("the portable renderer runs here")
                && line.contains("blades (WebGPU's defaults hold 2097152)")
                && line.contains(far),
            "{line}"
        );
    }
    assert!(adapter("Vulkan").contains("it folds a caller's depth"), "{stdout}");
    assert!(adapter("Gl").contains("cannot fold a caller's depth"), "{stdout}");
    // lavapipe draws indirect with a count, and the portable renderer uses it; llvmpipe's GL
    // has none of the optional features.
    assert!(
        adapter("Vulkan").contains("it uses multi-draw-indirect-count"),
        "{stdout}"
    );
    assert!(adapter("Gl").contains("has none of the optional features"), "{stdout}");
    if !listed[0].contains("draw routes: ") {
        return;
    }
    let name = listed[0].split(": ").nth(1).unwrap().split(" (").next().unwrap();
    let first = sward(&["info", "--gpu", "0"], &[]);
    assert!(
        String::from_utf8_lossy(&first.stdout).contains(&format!("device: {name}")),
        "--gpu 0 did not open {name}"
    );
}

/// One meaning per flag: render counts simulation steps (`--steps`), and its old `--frames`
/// says so instead of meaning something else than the viewer's.
#[test]
fn render_counts_steps_and_its_frames_flag_says_so() {
    fails_with(
        &sward(&["render", "--frames", "2"], &[]),
        &["--steps 2", "--frames is the number of frames `view` and `bench` draw"],
    );
}

#[test]
fn unknown_gpu() {
    fails_with(
        &sward(&["info", "--gpu", "Voodoo5"], &[]),
        &["--gpu Voodoo5 matches no usable Vulkan device", "0: "],
    );
}

#[test]
fn field_larger_than_the_gpu_holds() {
    // 2^26 blades = 4 GiB, past any device's single storage buffer (at most 2^32 − 1 bytes).
    rejects_scene(
        "huge.toml",
        "[field]\nblades = 67108864\n",
        &[
            "67108864 blades",
            "lower field.blades to at most",
            "--set field.blades=",
        ],
    );
}

#[test]
fn set_overrides_a_scene_value_and_rejects_unknown_keys() {
    let out_path = scratch("set.png");
    let out = sward(
        &[
            "render",
            "--set",
            "field.blades=500",
            "--set",
            "wind.type=whirl",
            "--width",
            "64",
            "--height",
            "48",
        ]
        .iter()
        .copied()
        .chain(["--steps", "2", "--out", out_path.to_str().unwrap()])
        .collect::<Vec<_>>(),
        &[],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("500 blades"));
    fails_with(
        &sward(&["render", "--set", "wind.strenght=2"], &[]),
        &["--set wind.strenght", "no such key", "did you mean wind.strength?"],
    );
    // Bad paint: a missing map, a file that is no PNG, a weight that is no number.
    let not_png = std::env::temp_dir().join(format!("sward-not-a-png-{}.png", std::process::id()));
    std::fs::write(&not_png, "P5 2 2 255").unwrap();
    fails_with(
        &sward(&["render", "--set", "paint.density=\"/nonexistent/path.png\""], &[]),
        &["paint map /nonexistent/path.png", "PNG"],
    );
    let color = format!("paint.color=\"{}\"", not_png.display());
    fails_with(
        &sward(&["render", "--set", &color], &[]),
        &["sward-not-a-png", "a paint map is a PNG image"],
    );
    fails_with(
        &sward(&["render", "--set", "species=[{name=\"a\",weight=nan}]"], &[]),
        &["species.0.weight", "finite"],
    );
    fails_with(
        &sward(
            &["render", "--set", "species=[{name=\"a\",seed_heads={share=2.0}}]"],
            &[],
        ),
        &["species.a.seed_heads.share", "a share from 0 to 1"],
    );
    fails_with(
        &sward(&["render", "--set", "field.height=[-1.0, 1.0]"], &[]),
        &["field.height", "0 < min"],
    );
}

#[test]
fn mesh_file_that_cannot_be_loaded() {
    rejects_scene(
        "badmesh.toml",
        "[surface]\ntype = \"mesh\"\npath = \"nope.obj\"\nscale = 1.0\n",
        &["cannot load mesh", "nope.obj", "OBJ"],
    );
}

#[test]
fn height_map_that_cannot_be_loaded() {
    rejects_scene(
        "badmap.toml",
        "[surface]\ntype = \"heightmap\"\npath = \"nowhere.png\"\nsize = [10.0, 10.0]\nheight = 2.0\n",
        &["cannot load mesh", "nowhere.png", "height maps"],
    );
}

#[test]
fn technique_picks_the_instanced_field_and_rejects_unknown_names() {
    let out_path = scratch("instanced.png");
    let args = [
        "render",
        "--technique",
        "instanced",
        "--width",
        "64",
        "--height",
        "48",
        "--steps",
        "1",
    ];
    let out = sward(
        &args
            .iter()
            .copied()
            .chain(["--out", out_path.to_str().unwrap()])
            .collect::<Vec<_>>(),
        &[],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("the instanced grass"));
    assert!(out_path.exists());
    // On terrain, with no Bezier field at all: draws and shuts down cleanly.
    let hills = sward(
        &["render", "--scene", "hills", "--technique", "instanced"]
            .iter()
            .copied()
            .chain([
                "--width",
                "64",
                "--height",
                "48",
                "--steps",
                "1",
                "--out",
                out_path.to_str().unwrap(),
            ])
            .collect::<Vec<_>>(),
        &[],
    );
    assert!(hills.status.success(), "{}", String::from_utf8_lossy(&hills.stderr));
    // clap's own message: the bad value and the allowed ones.
    let bad = sward(&["render", "--technique", "sprites"], &[]);
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success() && stderr.contains("sprites") && stderr.contains("bezier, instanced, both"));
    fails_with(
        &sward(&["render", "--set", "instanced.lod_distances=[50.0, 10.0, 70.0]"], &[]),
        &["instanced.lod_distances", "first < second"],
    );
    fails_with(
        &sward(&["render", "--set", "instanced.splat_distance=-5"], &[]),
        &["instanced.splat_distance", "positive distance"],
    );
    fails_with(
        &sward(&["bench", "--quick", "--set", "instanced.splat_distance=0"], &[]),
        &["instanced.splat_distance", "positive distance"],
    );
    // Counts above 2^26 set a generated field's density; a Bezier field holds no more.
    fails_with(
        &sward(&["bench", "--quick", "--presets", "meadow", "--counts", "2^27"], &[]),
        &["134217728 blades", "--technique instanced or billboard"],
    );
    let too_many = sward(&["bench", "--quick", "--counts", "2^29"], &[]);
    let stderr = String::from_utf8_lossy(&too_many.stderr);
    assert!(
        !too_many.status.success() && stderr.contains("2^N with N ≤ 28"),
        "{stderr}"
    );
    fails_with(
        &sward(
            &["render", "--technique", "billboard", "--set", "billboard.radius=-3"],
            &[],
        ),
        &["billboard.radius", "positive cut-off radius"],
    );
    fails_with(
        &sward(&["render", "--set", "billboard.height=[1.0, 0.2]"], &[]),
        &["billboard.height", "min ≤ max"],
    );
    fails_with(
        &sward(&["render", "--set", "billboard.sprites=4"], &[]),
        &["billboard.sprites", "no such key"],
    );
}

#[test]
fn bad_bodies_winds_and_shading_name_what_is_wrong() {
    rejects_scene(
        "body.toml",
        "[[body]]\nshape = { type = \"mesh\", path = \"rock.obj\", scale = 1.0 }\nspheres = 8\ncenter = [0.0, 1.0, 0.0]\n",
        &["body.shape", "rock.obj", "closed mesh"],
    );
    rejects_scene(
        "spheres.toml",
        "[[body]]\nshape = { type = \"boulder\", radius = 1.0, seed = 1 }\nspheres = 0\ncenter = [0.0, 1.0, 0.0]\n",
        &["body.spheres", "1 to 64"],
    );
    rejects_scene("winds.toml", &"[[wind]]\n".repeat(5), &["wind", "one to four"]);
    rejects_scene(
        "ao.toml",
        "[shading]\nambient_occlusion = 2.0\n",
        &["shading.ambient_occlusion", "[0, 1]"],
    );
    rejects_scene(
        "margin.toml",
        "[cull]\ntile_margin = -1.0\n",
        &["cull.tile_margin", "≥ 0"],
    );
}

/// A field whose size leaves no room for its blades (it panicked growing the meadow on 24 ×
/// 1e-30 units), and a generated grid with more items in its radius than a frame can list, are
/// refused in one sentence naming the key.
#[test]
fn a_field_too_thin_or_too_dense_for_its_blades_is_refused() {
    let meadow = include_str!("../../../scenes/meadow.toml");
    for (name, size) in [
        ("thin.toml", "[24.0, 1e-30]"),
        ("dense.toml", "[1e-30, 1e-30]"),
        ("strip.toml", "[1e-6, 24.0]"),
    ] {
        let text = meadow.replace("size = [24.0, 24.0]", &format!("size = {size}"));
        assert_ne!(text, meadow, "the meadow's size line moved");
        rejects_scene(name, &text, &["field.size", "leave room for the 60000 blades"]);
    }
    rejects_scene(
        "wide.toml",
        "technique = \"instanced\"\n[instanced]\ndensity = 10000.0\nradius = 100000.0\n",
        &["instanced.radius", "at most 268435456"],
    );
}

/// `sward shaders --out DIR` writes every portable pipeline's whole WGSL as a browser compiles
/// it, one file each, that declares the frame's blocks it reads and its entry point; a folder that cannot be made
/// is one sentence.
#[test]
fn writes_the_portable_wgsl_a_file_per_pipeline() {
    let dir = scratch("wgsl");
    let _ = std::fs::remove_dir_all(&dir);
    let out = sward(&["shaders", "--out", dir.to_str().unwrap()], &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let expected = [
        ("simulate", "fn simulate("),
        ("count_buckets", "fn count_buckets("),
        ("lay_out_buckets", "fn lay_out_buckets("),
        ("scan_buckets", "fn scan_buckets("),
        ("place_blades", "fn place_blades("),
        ("count_buckets_subgroups", "subgroupExclusiveAdd("),
        ("scan_buckets_subgroups", "fn scan_buckets("),
        ("place_blades_subgroups", "fn place_blades("),
        ("strips", "fn strip_fragment("),
        ("ground", "fn ground_fragment("),
        ("colliders", "fn collider_fragment("),
        ("sky", "fn sky_fragment("),
        ("occluder_blades", "fn occluder_vertex("),
        ("occluder_ground", "fn occluder_depth("),
        ("occluder_colliders", "fn collider_vertex("),
        ("reduce_pyramid", "fn reduce_level("),
        ("occluder_ground_whole", "fn ground_vertex("),
        ("trample", "fn trample("),
        ("fold_caller_depth", "fn fold_caller_depth("),
        ("fold_caller_depth_samples", "fn fold_caller_depth_samples("),
        ("rebase_field", "fn rebase_field("),
        ("make_entering_tiles", "fn make_entering_tiles("),
        ("cull_patches", "fn cull_patches("),
        ("count_generated", "fn count_generated("),
        ("scan_generated", "fn scan_generated("),
        ("place_generated", "fn place_generated("),
        ("count_billboards", "fn count_billboards("),
        ("scan_billboards", "fn scan_billboards("),
        ("place_billboards", "fn place_billboards("),
        ("generated_strips", "fn generated_vertex("),
        ("billboards", "fn billboard_fragment("),
        ("shadow_ground", "fn ground_vertex("),
        ("shadow_colliders", "fn collider_vertex("),
        ("shadow_blades", "fn strip_vertex("),
        ("shadow_generated", "fn generated_vertex("),
        ("lay_out_buckets_narrow", "fn lay_out_buckets("),
        ("sort_drawn_narrow", "fn sort_drawn("),
    ];
    let mut written: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name != "narrow")
        .collect();
    written.sort();
    let mut names: Vec<String> = expected.iter().map(|(n, _)| format!("{n}.wgsl")).collect();
    names.sort();
    assert_eq!(written, names);
    // The splatting passes in 32-bit cells, as a browser's device splats: no 64-bit integer.
    let narrow: Vec<String> = std::fs::read_dir(dir.join("narrow"))
        .unwrap()
        .map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap())
        .collect();
    assert_eq!(narrow.len(), sward_core::wgsl::splatting::PORTABLE_SPLATTING.len());
    assert!(
        narrow.iter().all(|text| !text.contains("u64")),
        "a narrow splatting pass names u64"
    );
    for (name, entry) in expected {
        let text = std::fs::read_to_string(dir.join(format!("{name}.wgsl"))).unwrap();
        let stages = text.contains("@compute") || (text.contains("@vertex") && text.contains("@fragment"));
        assert!(stages, "{name}: not a compute or a vertex and fragment stage");
        // Every pass reads a block of the frame's but the pyramid's reduction and the caller's
        // depth fold, which read only its levels (the structs sward-core declares, under their
        // composed names).
        let frame = text.lines().any(|line| {
            let block = |ty: &str| line.ends_with(&format!("_declared_{ty} {{"));
            line.starts_with("struct ") && sward_core::declared::BLOCKS.iter().any(|b| block(b.ty))
        });
        let levels_only = name == "reduce_pyramid" || name.starts_with("fold_caller_depth");
        assert_eq!(frame, !levels_only, "{name}: a frame block declared or not");
        assert!(text.contains(entry), "{name}: no entry point {entry}");
        assert!(!text.contains("#include"), "{name}: an unresolved include");
        assert!(
            !text.lines().any(|line| line.starts_with("import ")),
            "{name}: an import WESL left unresolved"
        );
        // As a browser compiles it: the subgroups extension enabled first where a pipeline uses
        // it (wgpu's naga refuses the directive, Chromium's Tint needs it).
        let enables = text.lines().nth(1) == Some("enable subgroups;");
        assert_eq!(
            enables,
            name.ends_with("_subgroups"),
            "{name}: `enable subgroups;` first, or not"
        );
    }
    let file = scratch("not-a-folder");
    std::fs::write(&file, "x").unwrap();
    let out = sward(&["shaders", "--out", file.to_str().unwrap()], &[]);
    fails_with(&out, &["cannot make the folder", "not-a-folder"]);
}

/// `render --renderer wgpu` draws with the portable renderer on wgpu's Vulkan and GL backends,
/// says so, and shows grass below the sky: the meadow, its generated grass, and the open world
/// — its streamed window of Bezier blades over its terrain, the generated grass and the
/// billboards to the horizon — seen from its path's start above the ground.
#[test]
fn renders_with_the_portable_renderer_on_wgpus_vulkan_and_gl_backends() {
    let scenes: [(&str, &[&str]); 3] = [
        ("meadow", &["--set", "field.blades=4000"]),
        (
            "meadow-instanced",
            &[
                "--technique",
                "instanced",
                "--set",
                "instanced.radius=30",
                "--set",
                "instanced.lod_distances=[4,10,20]",
            ],
        ),
        ("openworld", &["--scene", "openworld"]),
    ];
    for ((backend, said), (name, scene)) in [("vulkan", "on wgpu Vulkan"), ("gl", "on wgpu Gl")]
        .into_iter()
        .flat_map(|b| scenes.iter().map(move |s| (b, *s)))
    {
        let png = scratch(&format!("portable-{name}-{backend}.png"));
        let _ = std::fs::remove_file(&png);
        let args = [
            "render",
            "--renderer",
            "wgpu",
            "--wgpu-backend",
            backend,
            "--validation",
            "--width",
            "160",
            "--height",
            "120",
            "--steps",
            "12",
            "--out",
            png.to_str().unwrap(),
        ];
        let out = sward(&[&args[..], scene].concat(), &[]);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{name} on {backend}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            stdout.contains("portable renderer") && stdout.contains(said),
            "{stdout}"
        );
        let image = image::open(&png).unwrap().to_rgb8();
        assert_eq!(image.dimensions(), (160, 120));
        // Grass in the lower half, sky above: more green than blue below, the reverse above.
        let greener = |y0, y1| {
            let rows = (y0..y1).flat_map(|y| (0..160).map(move |x| (x, y)));
            rows.filter(|&(x, y)| {
                let p = image.get_pixel(x, y);
                p[1] > p[2]
            })
            .count()
        };
        assert!(
            greener(90, 120) > 160 * 30 * 9 / 10,
            "{name} on {backend}: no grass below"
        );
        assert!(greener(0, 20) < 160 * 20 / 10, "{name} on {backend}: no sky above");
    }
}

/// What the portable renderer cannot draw yet is refused in one sentence that says what it
/// can, and a backend this machine lacks is one sentence too.
#[test]
fn the_portable_renderer_refuses_what_it_cannot_draw_yet_in_one_sentence() {
    let png = scratch("never-portable.png");
    let png = png.to_str().unwrap();
    let cases: [(&[&str], &[&str]); 2] = [
        (
            &["--animation", "3"],
            &["writes stills", "--animation", "--renderer vulkan"],
        ),
        (&["--wgpu-backend", "metal"], &["finds no Metal adapter"]),
    ];
    for (extra, needles) in cases {
        let args = [&["render", "--renderer", "wgpu", "--out", png][..], extra].concat();
        fails_with(&sward(&args, &[]), needles);
    }
}

/// A small, quick frame: what the render tests that only need some grass ask for.
const SMALL_RENDER: [&str; 8] = [
    "--width",
    "160",
    "--height",
    "120",
    "--steps",
    "6",
    "--set",
    "field.blades=3000",
];

/// The portable renderer without its SPIR-V pass-through and its subgroups (`--without
/// spirv-passthrough,subgroups`: wgpu's own translation of its WGSL, the passes for WebGPU's core)
/// draws the picture it draws with them, on lavapipe.
#[test]
fn the_portable_renderer_draws_the_same_without_its_pass_through_and_subgroups() {
    let picture = |name: &str, extra: &[&str]| {
        let png = scratch(name);
        let args = [
            &["render", "--renderer", "wgpu"][..],
            &SMALL_RENDER,
            &["--out", png.to_str().unwrap()],
        ]
        .concat();
        let out = sward(&[extra, &args[..]].concat(), &[]);
        assert!(
            out.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        image::open(&png).unwrap().to_rgba8().into_raw()
    };
    let with = picture("with-passthrough.png", &[]);
    let without = picture("without-passthrough.png", &["--without", "spirv-passthrough,subgroups"]);
    let differing = with
        .chunks(4)
        .zip(without.chunks(4))
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    assert!(
        differing * 2000 <= with.len() / 4,
        "{differing} pixels differ by more than 8 levels"
    );
}

/// `--renderer auto` (the default) on a machine without a Vulkan driver draws with the portable
/// renderer on wgpu's GL backend, and says why.
#[test]
fn without_a_vulkan_driver_render_falls_back_to_the_portable_renderer_and_says_so() {
    let png = scratch("auto-fallback.png");
    let _ = std::fs::remove_file(&png);
    let none = [
        ("VK_DRIVER_FILES", "/nonexistent/icd.json"),
        ("VK_ICD_FILENAMES", "/nonexistent/icd.json"),
    ];
    let args = [&["render"][..], &SMALL_RENDER, &["--out", png.to_str().unwrap()]].concat();
    let out = sward(&args, &none);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stderr}");
    assert!(stdout.contains("portable renderer on wgpu Gl"), "{stdout}");
    assert!(
        stderr.contains("no Vulkan device sward can use") && stderr.contains("drawing with the portable renderer"),
        "{stderr}"
    );
    assert_eq!(image::open(&png).unwrap().to_rgb8().dimensions(), (160, 120));
}
