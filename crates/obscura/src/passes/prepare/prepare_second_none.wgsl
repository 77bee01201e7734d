// The prepare pass without a second depth layer (prepare_second.wgsl's interface).
fn store_second(pixel: vec2<u32>) {}
