//! The `obscura` executable end to end: a small render, and bad input that must end in a
//! clear message, a non-zero exit, no panic and no output file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod bench;
mod budget;
mod depth_maps;
mod eval;
mod eval_layers;
mod lights;
mod render;

fn obscura(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_obscura"))
        .args(args)
        .output()
        .expect("the obscura binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("obscura-cli-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `render --orbit 20` of the built-in scene at 96×64 for `frames` frames under
/// `--budget-ms budget` (and `control`, or the default controller), checks that it
/// succeeded and wrote the last frame and the plot, and returns stderr and budget.csv's
/// rows split at the commas (the header skipped).
fn budget_orbit(
    name: &str,
    budget: &str,
    frames: u32,
    control: Option<&str>,
) -> (String, Vec<Vec<String>>) {
    let d = scratch(name);
    let frames_arg = frames.to_string();
    let out_png = d.join("ao.png");
    let mut args = vec![
        "render",
        "--width",
        "96",
        "--height",
        "64",
        "--orbit",
        "20",
        "--frames",
        &frames_arg,
        "--out-dir",
        s(&d),
        "--out",
        s(&out_png),
        "--budget-ms",
        budget,
    ];
    if let Some(c) = control {
        args.extend(["--budget-control", c]);
    }
    let out = obscura(&args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{err}");
    let last = d.join(format!("frame_{:04}.png", frames - 1));
    assert!(last.exists() && d.join("budget.svg").exists());
    let csv = std::fs::read_to_string(d.join("budget.csv")).unwrap();
    let rows = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    std::fs::remove_dir_all(d).unwrap();
    (err, rows)
}

fn assert_fails(name: &str, args: &[&str], message: &str) {
    let d = scratch(name);
    let ao = d.join("ao.png");
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["--out", s(&ao)]);
    let out = obscura(&all);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{name}: should fail");
    assert!(!err.contains("panicked"), "{name}: panicked: {err}");
    assert!(
        err.to_lowercase().contains(&message.to_lowercase()),
        "{name}: expected `{message}` in: {err}"
    );
    assert!(!ao.exists(), "{name}: left an output file");
    let n = std::fs::read_dir(&d).unwrap().count();
    assert_eq!(n, 0, "{name}: left files behind");
    std::fs::remove_dir_all(d).unwrap();
}

/// The record of `variant` in `eval --json`'s output `v`.
fn record(v: &serde_json::Value, variant: &str) -> serde_json::Value {
    v["records"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["variant"] == variant)
        .unwrap_or_else(|| panic!("no {variant} in {v}"))
        .clone()
}

/// A JSON file, parsed.
fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `obscura eval --view cornell` on the shared scenes with `args`, writing its report, its
/// JSON (if given) and its reference cache where it is told.
fn eval_cornell(args: &[&str], report: &Path, json: Option<&Path>, cache: &Path) -> Output {
    let scenes = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/scenes");
    let mut all = vec!["eval", "--view", "cornell", "--scenes-dir", scenes];
    all.extend_from_slice(args);
    all.extend(["--report", s(report), "--cache", s(cache)]);
    if let Some(j) = json {
        all.extend(["--json", s(j)]);
    }
    obscura(&all)
}

/// `eval --view VIEW` (shared scenes, one run, 2×2 layers, no pictures) with `args`, its
/// JSON and reference cache in `d`; the run must succeed.
fn eval_view(d: &Path, view: &str, args: &[&str]) -> serde_json::Value {
    eval_view_logged(d, view, args).0
}

/// [`eval_view`] with what eval printed on stderr.
fn eval_view_logged(d: &Path, view: &str, args: &[&str]) -> (serde_json::Value, String) {
    let (json, cache) = (d.join("q.json"), d.join("cache"));
    let scenes = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/scenes");
    let mut all = vec![
        "eval",
        "--view",
        view,
        "--scenes-dir",
        scenes,
        "--runs",
        "1",
    ];
    all.extend(["--modes", "deinterleaved2"]);
    all.extend_from_slice(args);
    all.extend(["--cache", s(&cache), "--json", s(&json)]);
    let out = obscura(&all);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{err}");
    (read_json(&json), err)
}

/// The float32 payload of a 2-D C-order `.npy` of shape (h, w), checking its header.
fn read_npy_f32(path: &Path, h: usize, w: usize) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(
        header.contains("'<f4'") && header.contains(&format!("({h}, {w})")),
        "{header}"
    );
    assert_eq!((10 + len) % 64, 0, "data aligned to 64 bytes");
    let data = &bytes[10 + len..];
    assert_eq!(data.len(), 4 * w * h);
    data.chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// A `.npy` of `values` with `shape` (little-endian float32, C order).
fn npy_f32(shape: &[usize], values: &[f32]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let header = format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({},), }}\n",
        dims.join(", ")
    );
    let mut npy = b"\x93NUMPY\x01\x00".to_vec();
    npy.extend((header.len() as u16).to_le_bytes());
    npy.extend(header.as_bytes());
    npy.extend(values.iter().flat_map(|v| v.to_le_bytes()));
    npy
}

/// The error column of the table row whose variant is `variant` (a float), if any.
fn table_error(table: &str, variant: &str) -> Option<f64> {
    table
        .lines()
        .find(|l| l.split('|').nth(2).map(str::trim) == Some(variant))
        .and_then(|l| l.split('|').nth(5))
        .and_then(|c| c.trim().parse().ok())
}
