//! Every flag of `render`, `eval`, `lights`, `bench` and `cost`, run at least once at small sizes:
//! a flag that is accepted does its job (the output changes where it should, a file is
//! written where it should), or it is refused with the reason (exit 1, or clap's 2 for a
//! malformed argument) and no output is left. A flag added without a row here fails
//! `every_flag_has_a_row`.

use obscura::depth_map::npy_f32;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn obscura(args: &[String]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_obscura"))
        .args(args)
        .output()
        .expect("the obscura binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("obscura-flags-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn shared(path: &str) -> String {
    format!("{}/../../../shared/{path}", env!("CARGO_MANIFEST_DIR"))
}

/// What a row expects of its flag.
#[derive(Debug, Clone, Copy)]
enum Expect {
    /// The output differs from the same command without the row's flags.
    Changes,
    /// The output is the same: the flag changes how, not what (a timing or a pass layout
    /// that is the same computation).
    Same,
    /// The run succeeds and writes this file (relative to the row's folder).
    Writes(&'static str),
    /// The run fails (exit 1, or 2 for clap) with this text in its message, and leaves
    /// nothing in the row's folder.
    Refused(&'static str),
}

/// One row: a name, the base command (before the row's flags), the row's flags, and what
/// it expects. `{d}` in an argument is the row's folder.
struct Row {
    base: Vec<String>,
    flags: Vec<String>,
    expect: Expect,
}

fn words(s: &str) -> Vec<String> {
    s.split_whitespace().map(String::from).collect()
}

fn row(base: &str, flags: &str, expect: Expect) -> Row {
    Row {
        base: words(base),
        flags: words(flags),
        expect,
    }
}

/// The bytes of every file in `d`, by name: what a run wrote.
fn outputs(d: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            let mut bytes = std::fs::read(&p).unwrap();
            // eval's JSON holds each variant's time: compare everything else.
            if name.ends_with(".json") {
                let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
                if let Some(records) = v["records"].as_array_mut() {
                    for r in records {
                        r["median_ms"] = serde_json::Value::Null;
                    }
                }
                bytes = v.to_string().into_bytes();
            }
            (name, bytes)
        })
        .collect();
    v.sort();
    v
}

/// `{d}`: the row's folder; `{depth}`: the depth-map inputs; `{cache}`: eval's reference
/// cache, shared by the rows; `{shared}`: ../shared.
fn expand(args: &[String], d: &Path) -> Vec<String> {
    let common = std::env::temp_dir().join(format!("obscura-flags-{}", std::process::id()));
    args.iter()
        .map(|a| {
            a.replace("{d}", d.to_str().unwrap())
                .replace("{depth}", common.join("depth").to_str().unwrap())
                .replace("{cache}", common.join("cache").to_str().unwrap())
                .replace("{shared}", &shared(""))
        })
        .collect()
}

/// The flag's name of an argument (`--width`, `--camera=…`), if it is one.
fn flag_of(a: &str) -> Option<&str> {
    a.starts_with("--").then(|| a.split('=').next().unwrap())
}

/// `base` with `flags` added, each flag given in both taking the row's value.
fn merged(base: &[String], flags: &[String]) -> Vec<String> {
    let given: Vec<&str> = flags.iter().filter_map(|a| flag_of(a)).collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < base.len() {
        match flag_of(&base[i]) {
            Some(f) if given.contains(&f) => {
                // Its value too, unless the flag is a switch or carries it after `=`.
                let has_value =
                    !base[i].contains('=') && base.get(i + 1).is_some_and(|v| !v.starts_with("--"));
                i += 1 + has_value as usize;
            }
            _ => {
                out.push(base[i].clone());
                i += 1;
            }
        }
    }
    out.extend(flags.iter().cloned());
    out
}

/// Runs `rows`, each in its own folder; returns one line per failed row.
fn check(name: &str, rows: &[Row]) -> Vec<String> {
    let mut failed = Vec::new();
    for (i, r) in rows.iter().enumerate() {
        let d = scratch(&format!("{name}-{i}"));
        let with = merged(&r.base, &r.flags);
        let out = obscura(&expand(&with, &d));
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        let code = out.status.code();
        let label = format!("{name} `{}`", r.flags.join(" "));
        if err.contains("panicked") {
            failed.push(format!("{label}: panicked: {err}"));
            continue;
        }
        match r.expect {
            Expect::Refused(text) => {
                if !matches!(code, Some(1 | 2)) || !err.contains(text) {
                    failed.push(format!(
                        "{label}: exit {code:?}, expected a refusal `{text}`: {err}"
                    ));
                } else if std::fs::read_dir(&d).unwrap().next().is_some() {
                    failed.push(format!("{label}: refused but left files"));
                }
            }
            Expect::Writes(file) => {
                if code != Some(0) || !d.join(file).exists() {
                    failed.push(format!("{label}: exit {code:?}, expected {file}: {err}"));
                }
            }
            Expect::Changes | Expect::Same => {
                let with_out = outputs(&d);
                let base_d = scratch(&format!("{name}-{i}-base"));
                let base = obscura(&expand(&r.base, &base_d));
                let base_out = outputs(&base_d);
                let same = with_out == base_out;
                if code != Some(0) || !base.status.success() {
                    failed.push(format!("{label}: exit {code:?}: {err}"));
                } else if with_out.is_empty() {
                    failed.push(format!("{label}: wrote nothing"));
                } else if same != matches!(r.expect, Expect::Same) {
                    failed.push(format!(
                        "{label}: output {}",
                        if same { "unchanged" } else { "changed" }
                    ));
                }
                let _ = std::fs::remove_dir_all(base_d);
            }
        }
        let _ = std::fs::remove_dir_all(d);
    }
    failed
}

const RENDER: &str = "render --width 64 --height 48 --out {d}/ao.npy";
const DEPTH: &str =
    "render --runs 1 --depth {depth}/d.npy --intrinsics {depth}/k.json --out {d}/ao.npy";

/// `render`'s rows: every flag with each input kind where it applies, and refused where
/// it does nothing.
fn render_rows() -> Vec<Row> {
    use Expect::*;
    let hbao = format!("{RENDER} --estimator hbao");
    let sao = format!("{RENDER} --estimator sao");
    let bitmask = format!("{RENDER} --estimator bitmask");
    let layered = format!(
        "{RENDER} --estimator bitmask --second-layer --thickness 0.75 --directions 3 --steps 7 \
         --march-exponent 1.3 --guard-band 16"
    );
    let half = format!("{RENDER} --resolution half");
    let scaled = format!("{RENDER} --resolution scaled");
    let ortho = format!("{RENDER} --projection orthographic");
    let frames = format!("{RENDER} --frames 3");
    let png = "render --width 64 --height 48 --out {d}/ao.png";
    let orbit =
        "render --width 64 --height 48 --orbit 10 --frames 2 --out {d}/ao.png --out-dir {d}/o";
    let ssdo = format!("{RENDER} --ssdo {{d}}/lit.exr");
    let normals = format!("{DEPTH} --normals-file {{depth}}/n.npy");
    let cornell = format!("{RENDER} --scene {{shared}}scenes/cornell_box/cornell_box.glb");
    let refused = "does nothing here";
    vec![
        row(
            RENDER,
            "--scene {shared}scenes/cornell_box/cornell_box.glb",
            Changes,
        ),
        row(&cornell, "--camera=0,2,8,0,1,0,50", Changes),
        row(RENDER, "--up 0,0,1", Changes),
        row(RENDER, "--projection orthographic", Changes),
        row(RENDER, "--fov 30", Changes),
        row(&ortho, "--ortho-height 3", Changes),
        row(RENDER, "--near 2", Changes),
        row(RENDER, "--far 5", Changes),
        row(RENDER, "--width 48", Changes),
        row(RENDER, "--height 32", Changes),
        row(RENDER, "--radius 0.1", Changes),
        row(RENDER, "--estimator hbao", Changes),
        row(RENDER, "--preset low", Changes),
        row(RENDER, "--directions 1", Changes),
        row(RENDER, "--steps 1", Changes),
        row(RENDER, "--mode randomized", Changes),
        row(RENDER, "--unfused", Same),
        row(RENDER, "--resolution half", Changes),
        row(&scaled, "--scale 0.5", Changes),
        row(&half, "--downsample max", Changes),
        row(&half, "--upsample nearest-depth", Changes),
        row(RENDER, "--denoise none", Changes),
        row(&sao, "--pyramid four", Same),
        row(&hbao, "--bias 40", Changes),
        row(RENDER, "--strength 0.3", Changes),
        row(&bitmask, "--thickness 0.05", Changes),
        row(RENDER, "--march-exponent 3", Changes),
        row(RENDER, "--max-radius-px 2", Changes),
        row(RENDER, "--normals reconstruct", Changes),
        row(RENDER, "--msaa", Changes),
        row(RENDER, "--guard-band 16", Changes),
        row(&bitmask, "--second-layer", Changes),
        // --layered is its flag set (obscura::AoOptions::layered, its prior and band).
        row(&layered, "--layered", Same),
        row(RENDER, "--layered", Changes),
        row(DEPTH, "--layered", Refused("cannot be used with")),
        // A depth map alone takes the bitmask (obscura::DEPTH_MAP_ESTIMATOR).
        row(DEPTH, "--estimator bitmask", Same),
        row(DEPTH, "--estimator gtao", Changes),
        row(DEPTH, "--depth-noise 0.05,0,0", Changes),
        row(DEPTH, "--normals-file {depth}/n.npy", Changes),
        row(&normals, "--normals-frame opengl", Changes),
        row(png, "--bits 16", Changes),
        row(RENDER, "--depth-out {d}/depth.png", Writes("depth.png")),
        row(RENDER, "--normals-out {d}/n.png", Writes("n.png")),
        row(DEPTH, "--depth-out {d}/depth.png", Writes("depth.png")),
        row(DEPTH, "--normals-out {d}/n.png", Writes("n.png")),
        row(RENDER, "--bent-normals-out {d}/b.png", Writes("b.png")),
        row(RENDER, "--runs 2", Same),
        row(RENDER, "--frames 3", Changes),
        row(&frames, "--history 2", Changes),
        row(
            RENDER,
            "--orbit 10 --frames 2 --out-dir {d}/o",
            Writes("o/frame_0001.png"),
        ),
        row(orbit, "--budget-ms 500", Writes("o/budget.csv")),
        row(
            &format!("{orbit} --budget-ms 500"),
            "--budget-control scale",
            Writes("o/budget.csv"),
        ),
        row(RENDER, "--ssdo {d}/lit.exr", Writes("lit.exr")),
        row(&ssdo, "--env white", Changes),
        // Refused where they would do nothing.
        row(
            DEPTH,
            "--fov 30",
            Refused("a depth map's camera is its --intrinsics"),
        ),
        row(DEPTH, "--camera=0,2,8,0,1,0", Refused(refused)),
        row(
            DEPTH,
            "--width 32",
            Refused("a depth map's AO has the map's size"),
        ),
        row(DEPTH, "--normals reconstruct", Refused(refused)),
        row(RENDER, "--bias 20", Refused("tangent bias of hbao and sao")),
        row(
            RENDER,
            "--thickness 0.5",
            Refused("the bitmask's thickness prior"),
        ),
        row(
            &hbao,
            "--march-exponent 2",
            Refused("only gtao and the bitmask march"),
        ),
        row(RENDER, "--pyramid one", Refused("read a depth pyramid")),
        row(RENDER, "--downsample max", Refused("below full resolution")),
        row(
            RENDER,
            "--mode randomized --unfused",
            Refused("no split, merge or downsample"),
        ),
        row(RENDER, "--history 4", Refused("accumulation")),
        row(
            RENDER,
            "--frames 3 --runs 3",
            Refused("time each of their own frames"),
        ),
        row(RENDER, "--bits 16", Refused("a PNG's bit depth")),
        row(&ortho, "--fov 30", Refused("a perspective camera's")),
        row(
            RENDER,
            "--ortho-height 3",
            Refused("--projection orthographic"),
        ),
        row(
            RENDER,
            "--camera=0,2,8,0,1,0,50 --fov 30",
            Refused("seventh value"),
        ),
        row(
            RENDER,
            "--msaa --normals gbuffer",
            Refused("--msaa reconstructs"),
        ),
        row(
            orbit,
            "--depth-out {d}/depth.png",
            Refused("--orbit writes its frames alone"),
        ),
        row(
            &bitmask,
            "--second-layer --thickness inf",
            Refused("needs a finite --thickness"),
        ),
        row(RENDER, "--env white", Refused("--ssdo")),
        row(RENDER, "--out-dir {d}/o", Refused("--orbit")),
        row(RENDER, "--normals-frame opengl", Refused("--depth")),
        row(RENDER, "--width=-1", Refused("-1 is not in 1..=65536")),
    ]
}

/// A small depth map with intrinsics and normals, shared by the depth-map rows (`{depth}`).
fn depth_inputs() {
    let d = std::env::temp_dir()
        .join(format!("obscura-flags-{}", std::process::id()))
        .join("depth");
    std::fs::create_dir_all(&d).unwrap();
    let (w, h) = (64usize, 48usize);
    let mut depth = vec![3.0f32; w * h];
    for y in 0..h {
        for x in 0..w {
            if y > 30 {
                depth[y * w + x] = 2.0;
            }
            if (x as i32 - 32).abs() < 10 && y > 20 {
                depth[y * w + x] = 1.6;
            }
        }
    }
    std::fs::write(d.join("d.npy"), npy_f32(&depth, &[h as u32, w as u32])).unwrap();
    let normals: Vec<f32> = (0..w * h).flat_map(|_| [0.0, 0.0, -1.0]).collect();
    std::fs::write(d.join("n.npy"), npy_f32(&normals, &[h as u32, w as u32, 3])).unwrap();
    std::fs::write(
        d.join("k.json"),
        r#"{"fx": 60, "fy": 60, "cx": 31.5, "cy": 23.5, "width": 64, "height": 48}"#,
    )
    .unwrap();
}

const EVAL: &str = "eval --view cornell --scenes-dir {shared}scenes --width 32 --height 20 --rays 4 --runs 1 --estimators gtao --modes randomized --no-screen-reference --cache {cache} --json {d}/q.json";

/// `eval`'s rows. Each run traces a 32 × 20 view with 4 rays a pixel (cached across rows).
fn eval_rows() -> Vec<Row> {
    use Expect::*;
    let bitmask = EVAL.replace("--estimators gtao", "--estimators bitmask");
    let report = format!("{EVAL} --report {{d}}/r");
    let frames = format!("{EVAL} --frames 1,3");
    let layers = format!("{bitmask} --layer-limits 4x4");
    let ssdo = "eval --ssdo --view cornell --scenes-dir {shared}scenes --width 32 --height 20 --rays 4 --runs 1 --modes randomized --cache {cache} --report {d}/r";
    let refused = "does nothing here";
    vec![
        row(EVAL, "--radius 2", Changes),
        row(EVAL, "--falloff quadratic", Changes),
        row(EVAL, "--rays 8", Changes),
        row(EVAL, "--width 24", Changes),
        row(EVAL, "--height 16", Changes),
        row(EVAL, "--estimators hbao", Changes),
        row(EVAL, "--preset low", Changes),
        row(EVAL, "--directions 1", Changes),
        row(EVAL, "--steps 1", Changes),
        row(EVAL, "--splits 2x2,3x3", Changes),
        row(EVAL, "--presets low,high", Changes),
        row(EVAL, "--modes deinterleaved2", Changes),
        row(EVAL, "--resolutions full,half", Changes),
        row(EVAL, "--scales 0.5", Changes),
        row(&bitmask, "--thickness 0.5,1", Changes),
        row(EVAL, "--march-exponents 1,2", Changes),
        row(EVAL, "--guard-bands 0,8", Changes),
        row(&bitmask, "--second-layer", Changes),
        row(&bitmask, "--layer-limits 4x4", Changes),
        row(&layers, "--layer-jitter", Changes),
        row(&format!("{EVAL} --resolutions half"), "--downsamples max,min", Changes),
        row(&format!("{EVAL} --resolutions half"), "--upsamplers bilinear,bilateral", Changes),
        row(EVAL, "--denoise none,spatial", Changes),
        row(EVAL, "--normals reconstruct", Changes),
        row(EVAL, "--bent-normals", Changes),
        row(EVAL, "--frames 1,3", Changes),
        row(&frames, "--history 2", Changes),
        row(&frames, "--orbit-step 3", Changes),
        row(EVAL, "--sensor kinect", Changes),
        row(&format!("{EVAL} --sensor kinect"), "--sensor-noise 0", Changes),
        row(EVAL, "--depth-noise estimate", Same),
        row(EVAL, "--msaa", Changes),
        row(EVAL, "--traced-depth", Changes),
        row(EVAL, "--truth msaa4", Changes),
        row(EVAL, "--runs 2", Writes("q.json")),
        row(EVAL, "--report {d}/r", Writes("r/index.md")),
        row(&report, "--markdown {d}/r/other.md", Writes("r/other.md")),
        row(&report, "--picture-scale 1", Writes("r/cornell-reference.png")),
        row(&report, "--no-pictures", Writes("r/index.md")),
        row(EVAL, "--export-views {d}/views.json", Writes("views.json")),
        row(
            "eval --all --scenes-dir {shared}scenes --width 16 --height 10 --rays 1 --runs 1 --estimators gtao --modes randomized --no-screen-reference --cache {cache} --json {d}/q.json",
            "",
            Writes("q.json"),
        ),
        row(
            "eval --scene {shared}scenes/cornell_box/cornell_box.glb --width 32 --height 20 --rays 4 --runs 1 --estimators gtao --modes randomized --no-screen-reference --cache {cache} --json {d}/q.json",
            "--camera=0,2,8,0,1,0,50",
            Writes("q.json"),
        ),
        row(ssdo, "--env white", Writes("r/index.md")),
        row(ssdo, "--albedo-scale 0.5", Writes("r/index.md")),
        // --score-images has its own test in cli.rs (analytic images scored).
        // Refused where they would do nothing.
        row(EVAL, "--thickness 0.5", Refused("the bitmask's thickness prior")),
        row(EVAL, "--second-layer", Refused(refused)),
        row(&EVAL.replace("gtao", "vo"), "--march-exponents 2", Refused("march their steps")),
        row(EVAL, "--downsamples max", Refused("below full resolution")),
        row(EVAL, "--history 4", Refused("accumulation")),
        row(EVAL, "--orbit-step 2", Refused(refused)),
        row(EVAL, "--sensor-noise 0.5", Refused("--sensor")),
        row(EVAL, "--msaa --normals gbuffer", Refused("--msaa reconstructs")),
        row(EVAL, "--presets low,high --preset ultra", Refused("--presets or --splits")),
        row(EVAL, "--no-pictures", Refused("--report")),
        row(EVAL, "--picture-scale 1", Refused(refused)),
        row(&EVAL.replace("--estimators gtao", "--estimators vo"), "--bent-normals", Refused(refused)),
        row(EVAL, "--guard-bands=-1", Refused("0..=1024")),
        row(EVAL, "--json {d}/no/such/q.json", Refused("does not exist")),
    ]
}

const LIGHTS: &str =
    "lights --width 64 --height 48 --count 16 --periods 2 --runs 1 --out-dir {d}/l";

fn lights_rows() -> Vec<Row> {
    use Expect::*;
    vec![
        row(LIGHTS, "--seed 2", Writes("l/courtyard-all.png")),
        row(LIGHTS, "--count 8", Writes("l/courtyard-all.png")),
        row(LIGHTS, "--periods 2,4", Writes("l/courtyard-all.png")),
        row(LIGHTS, "--runs 2", Writes("l/courtyard-all.png")),
        row(LIGHTS, "--markdown {d}/lights.md", Writes("lights.md")),
        row(LIGHTS, "--view cornell --scenes-dir {shared}scenes", Writes("l/cornell-all.png")),
        row(LIGHTS, "--scene {shared}scenes/cornell_box/cornell_box.glb --camera=0,2,8,0,1,0,50", Writes("l/cornell_box-all.png")),
        row(
            "lights --width 16 --height 10 --count 4 --periods 2 --runs 1 --markdown {d}/all.md --scenes-dir {shared}scenes",
            "--all",
            Writes("all.md"),
        ),
        row(
            "lights --width 64 --height 48 --periods 2 --runs 1 --out-dir {d}/l",
            "--lights-file {d}/none.json",
            Refused("none.json"),
        ),
        row(LIGHTS, "--periods 3", Refused("2, 4 or 8")),
        row(LIGHTS, "--markdown {d}/no/l.md", Refused("does not exist")),
    ]
}

const BENCH: &str = "bench --resolutions 32x20 --radii 4 --runs 1 --json {d}/b.json";

fn bench_rows() -> Vec<Row> {
    use Expect::*;
    let w = Writes("b.json");
    vec![
        row(BENCH, "--compare resolutions", w),
        row(
            BENCH,
            "--resolution half --downsample max --upsample bilinear",
            w,
        ),
        row(BENCH, "--resolution scaled --scale 0.5", w),
        row(BENCH, "--denoise none --pyramid one", w),
        row(BENCH, "--mode randomized", w),
        row(
            BENCH,
            "--estimator hbao --preset low --directions 2 --steps 2",
            w,
        ),
        row(BENCH, "--normals reconstruct", w),
        row(BENCH, "--compare layouts --msaa", w),
        row(BENCH, "--compare layers --guard-band 8", w),
        row(BENCH, "--plot {d}/b.svg", Writes("b.svg")),
        row(BENCH, "--radii 4,8", w),
        row(BENCH, "--runs 2", w),
        row(BENCH, "--json {d}/no/b.json", Refused("does not exist")),
    ]
}

const COST: &str = "cost --width 64 --height 48 --json {d}/c.json";

/// `cost`'s rows: each flag changes the table (no adapter runs).
fn cost_rows() -> Vec<Row> {
    use Expect::*;
    let bitmask = format!("{COST} --estimator bitmask");
    vec![
        row(COST, "--width 32", Changes),
        row(COST, "--height 32", Changes),
        row(COST, "--mode randomized", Changes),
        row(COST, "--estimator bitmask", Changes),
        row(COST, "--preset low", Changes),
        row(COST, "--directions 2", Changes),
        row(COST, "--steps 2", Changes),
        row(COST, "--resolution half", Changes),
        row(COST, "--denoise none", Changes),
        row(COST, "--march-exponent 1", Changes),
        row(&bitmask, "--second-layer", Changes),
        row(COST, "--second-layer", Refused("second_layer")),
        row(COST, "--normals reconstruct", Changes),
        row(COST, "--json {d}/no/c.json", Refused("does not exist")),
    ]
}

/// The long flags a subcommand's `--help` lists.
fn help_flags(sub: &str) -> BTreeSet<String> {
    let out = obscura(&[sub.to_string(), "--help".to_string()]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    text.lines()
        .filter_map(|l| {
            let l = l.trim_start();
            let l = l.strip_prefix("-h, ").unwrap_or(l);
            l.strip_prefix("--")
                .map(|f| f.split([' ', '=', '<']).next().unwrap().to_string())
        })
        // A description line that starts with a flag's name and a colon is not an option.
        .filter(|f| f != "help" && f.chars().all(|c| c.is_ascii_lowercase() || c == '-'))
        .collect()
}

/// The flags a set of rows names.
fn named(rows: &[Row]) -> BTreeSet<String> {
    rows.iter()
        .flat_map(|r| r.base.iter().chain(&r.flags))
        .filter_map(|a| a.strip_prefix("--"))
        .map(|a| a.split('=').next().unwrap().to_string())
        .collect()
}

#[test]
fn every_flag_has_a_row() {
    for (sub, rows, elsewhere) in [
        ("render", render_rows(), &[][..]),
        ("eval", eval_rows(), &["score-images", "ssdo"][..]),
        ("lights", lights_rows(), &["width", "height", "out-dir"][..]),
        ("bench", bench_rows(), &[][..]),
        ("cost", cost_rows(), &[][..]),
    ] {
        let have = named(&rows);
        let missing: Vec<String> = help_flags(sub)
            .into_iter()
            .filter(|f| !have.contains(f) && !elsewhere.contains(&f.as_str()))
            .collect();
        assert!(
            missing.is_empty(),
            "{sub}: flags without a row: {missing:?}"
        );
    }
}

#[test]
fn every_render_flag_works_or_is_refused() {
    depth_inputs();
    let failed = check("render", &render_rows());
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn every_eval_flag_works_or_is_refused() {
    let failed = check("eval", &eval_rows());
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn every_lights_bench_and_cost_flag_works_or_is_refused() {
    let mut failed = check("lights", &lights_rows());
    failed.extend(check("bench", &bench_rows()));
    failed.extend(check("cost", &cost_rows()));
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
