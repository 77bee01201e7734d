// No bent normals: temporal_bent.wgsl's interface with nothing bound and nothing stored.

fn bent_history_tap(t: vec2<i32>, w: f32) {}

fn bent_finish(p: vec2<i32>, kept: bool, current_weight: f32) {}
