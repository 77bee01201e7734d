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
