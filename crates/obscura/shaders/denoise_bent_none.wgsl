// No bent normals: denoise_bent.wgsl's interface with nothing bound and nothing stored.

fn bent_tap(q: vec2<i32>, w: f32) {}

fn bent_store(p: vec2<i32>, filtered: bool) {}
