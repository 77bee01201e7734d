// No bent normals: denoise_bent.wgsl's interface with nothing bound and nothing stored.

fn bent_tap(q: vec2<i32>, w: f32, n: vec3<f32>, d: vec2<f32>) {}

fn bent_fit(total: f32, m: vec2<f32>, cov: vec3<f32>) {}

fn bent_store(p: vec2<i32>, n: vec3<f32>) {}
