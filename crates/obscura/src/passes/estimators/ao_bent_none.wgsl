// No bent normals: ao_bent.wgsl's interface with nothing bound and nothing stored.

var<private> bent_normal: vec3<f32>;

fn store_bent(full: vec2<u32>) {}
