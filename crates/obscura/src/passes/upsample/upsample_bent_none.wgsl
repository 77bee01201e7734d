// No bent normals: upsample_bent.wgsl's interface with nothing bound and nothing stored.

fn upsample_bent(p: vec2<i32>, w: vec4<f32>, centre: vec4<f32>, fp: Footprint) {}
