//! The browser test of the built-in scene (tests/web.rs) compares with the native AO of the
//! same view, which scripts/web-test.sh renders first and names in `OBSCURA_WEB_NATIVE`:
//! copied here into the build's output, or an empty file without it (the test then fails
//! and says how to run it).
fn main() {
    println!("cargo:rerun-if-env-changed=OBSCURA_WEB_NATIVE");
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .join("native_courtyard.npy");
    let bytes = match std::env::var("OBSCURA_WEB_NATIVE") {
        Ok(path) => {
            println!("cargo:rerun-if-changed={path}");
            std::fs::read(&path).unwrap_or_else(|e| panic!("OBSCURA_WEB_NATIVE `{path}`: {e}"))
        }
        Err(_) => Vec::new(),
    };
    std::fs::write(&out, bytes).expect("the build's output directory is writable");
}
