// sphere.wgsl's chords read by line integrals (VO, VAO): each sample's chord is occupied
// by the one depth of its pixel.

fn sample_level(rs_px: f32) -> i32 {
    return 0;
}

// Where the chord of the sample at pixel `q` runs: the pixel's centre.
fn chord_point(q: vec2<i32>, level: i32) -> vec2<f32> {
    return vec2<f32>(q) + 0.5;
}

fn chord_occupied(q: vec2<i32>, level: i32, dc: f32, h: f32) -> f32 {
    return line_occupied(q, dc, h);
}
