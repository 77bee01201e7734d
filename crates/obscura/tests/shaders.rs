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
