//! Every WGSL pass parses and validates with naga, and the uniform struct generated from
//! Rust has the same layout in WGSL. No GPU needed.

use obscura::shader::Pass;
use obscura::uniforms::FrameUniforms;

fn parse(pass: Pass) -> naga::Module {
    let src = pass.source();
    naga::front::wgsl::parse_str(&src)
        .unwrap_or_else(|e| panic!("{}: {}", pass.label(), e.emit_to_string(&src)))
}

#[test]
fn every_pass_validates() {
    for pass in Pass::all() {
        let module = parse(pass);
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", pass.label()));
    }
}

#[test]
fn frame_uniforms_layout_matches_wgsl() {
    let module = parse(Pass::AoFull {
        estimator: obscura::Estimator::Hbao,
        bent: false,
        second_layer: false,
        packed: false,
    });
    let (members, span) = module
        .types
        .iter()
        .find_map(|(_, t)| match (&t.name, &t.inner) {
            (Some(n), naga::TypeInner::Struct { members, span }) if n == "FrameUniforms" => {
                Some((members.clone(), *span))
            }
            _ => None,
        })
        .expect("FrameUniforms is declared in the prelude");
    let rust = FrameUniforms::field_offsets();
    assert_eq!(members.len(), rust.len());
    for (m, (name, offset)) in members.iter().zip(rust) {
        assert_eq!(m.name.as_deref(), Some(name));
        assert_eq!(m.offset as usize, offset, "offset of `{name}`");
    }
    assert_eq!(span as usize, std::mem::size_of::<FrameUniforms>());
}

/// Every pass stays within WebGPU's defaults, so the same WGSL can run in a browser: at
/// most 4 storage textures per shader stage (`maxStorageTexturesPerShaderStage`), and only
/// storage formats core WebGPU allows (no `r16float` storage, which needs a feature).
#[test]
fn every_pass_fits_webgpu_default_limits() {
    // WebGPU's core storage-texture formats (WebGPU spec, "Texture Format Capabilities").
    use naga::StorageFormat as S;
    let core = [
        S::Rgba8Unorm,
        S::Rgba8Snorm,
        S::Rgba8Uint,
        S::Rgba8Sint,
        S::Rgba16Uint,
        S::Rgba16Sint,
        S::Rgba16Float,
        S::R32Uint,
        S::R32Sint,
        S::R32Float,
        S::Rg32Uint,
        S::Rg32Sint,
        S::Rg32Float,
        S::Rgba32Uint,
        S::Rgba32Sint,
        S::Rgba32Float,
        S::Bgra8Unorm,
    ];
    for pass in Pass::all() {
        let module = parse(pass);
        let formats: Vec<naga::StorageFormat> = module
            .global_variables
            .iter()
            .filter_map(|(_, g)| match module.types[g.ty].inner {
                naga::TypeInner::Image {
                    class: naga::ImageClass::Storage { format, .. },
                    ..
                } => Some(format),
                _ => None,
            })
            .collect();
        assert!(
            formats.len() <= 4,
            "{}: {} storage textures",
            pass.label(),
            formats.len()
        );
        for f in formats {
            assert!(core.contains(&f), "{}: storage format {f:?}", pass.label());
        }
    }
}

/// WGSL tokens: identifiers and numbers whole, the operators a loop header uses as one
/// token each, anything else one character; comments dropped.
fn tokens(src: &str) -> Vec<String> {
    let code: Vec<&str> = src
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect();
    let chars: Vec<char> = code.join("\n").chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_alphanumeric() || c == '_' {
            let start = i;
            while i < chars.len()
                && (chars[i].is_alphanumeric()
                    || chars[i] == '_'
                    || chars[i] == '.' && chars[start].is_ascii_digit())
            {
                i += 1;
            }
            out.push(chars[start..i].iter().collect());
        } else {
            let two: String = chars[i..(i + 2).min(chars.len())].iter().collect();
            let ops = [
                "==", "!=", "<=", ">=", "++", "--", "+=", "-=", "*=", "/=", "&&", "||", "->",
            ];
            if ops.contains(&two.as_str()) {
                out.push(two);
                i += 2;
            } else {
                out.push(c.to_string());
                i += 1;
            }
        }
    }
    out
}

/// Every loop in the WGSL sources is a counted `for`: `for (var i = A; i < B; i++)` (or
/// `i <= B` with `i++`, `i > B` with `i--`) whose counter the body never assigns, so it
/// moves one step per iteration toward its bound. That is what lets `shader::create_module`
/// turn off wgpu's loop-bounding guard (`<=` bounds are texture sizes or small constants,
/// never the integer type's maximum). No `loop` or `while`.
#[test]
fn every_shader_loop_is_counted() {
    // Every pass's WGSL lives beside its CPU mirror under src/passes/ (one folder a pass).
    let mut dirs = vec![std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/passes")];
    let mut files = Vec::new();
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else {
                files.push(path);
            }
        }
    }
    let mut loops = 0;
    let mut wgsl_files = 0;
    for path in files {
        if path.extension().and_then(|e| e.to_str()) != Some("wgsl") {
            continue;
        }
        wgsl_files += 1;
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let t = tokens(&std::fs::read_to_string(&path).unwrap());
        for kw in ["loop", "while"] {
            assert!(
                !t.iter().any(|x| x == kw),
                "{name}: `{kw}` is not a counted loop"
            );
        }
        let mut counters = Vec::new();
        let mut in_header = vec![false; t.len()];
        for i in 0..t.len() {
            if t[i] != "for" {
                continue;
            }
            // for ( var N = ... ; N op ... ; N ++|-- )
            let close = (i..t.len()).find(|&j| t[j] == "{").expect("a loop body");
            let h = &t[i..close];
            let semis: Vec<usize> = (0..h.len()).filter(|&j| h[j] == ";").collect();
            assert!(
                h.len() >= 9 && h[1] == "(" && h[2] == "var" && h[4] == "=" && semis.len() == 2,
                "{name}: loop header `{}` is not `for (var i = a; i < b; i++)`",
                h.join(" ")
            );
            let n = &h[3];
            let (cond, step) = (&h[semis[0] + 1..semis[1]], &h[semis[1] + 1..]);
            let op = cond.get(1).map(String::as_str);
            let counted = cond[0] == *n
                && step.len() == 3
                && step[0] == *n
                && step[2] == ")"
                && match step[1].as_str() {
                    "++" => matches!(op, Some("<" | "<=")),
                    "--" => op == Some(">"),
                    _ => false,
                };
            assert!(
                counted,
                "{name}: loop header `{}` is not counted",
                h.join(" ")
            );
            counters.push(n.clone());
            in_header[i..close].iter_mut().for_each(|b| *b = true);
            loops += 1;
        }
        let assigns = ["=", "+=", "-=", "*=", "/=", "++", "--"];
        for j in 1..t.len() - 1 {
            let declared_or_member = matches!(t[j - 1].as_str(), "var" | "let" | "const" | ".");
            if !in_header[j] && counters.contains(&t[j]) && assigns.contains(&t[j + 1].as_str()) {
                assert!(
                    declared_or_member,
                    "{name}: loop counter `{}` assigned in a body",
                    t[j]
                );
            }
        }
    }
    assert!(
        loops >= 30 && wgsl_files >= 60,
        "found only {loops} loops in {wgsl_files} files: is the shader folder right?"
    );
}
