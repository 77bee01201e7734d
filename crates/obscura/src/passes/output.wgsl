// The store of a pass that can write obscura's output (the plan's last pass; the pass
// declares `ao_out`). With CROPS (set for the output step of a frame with a guard band,
// crate::AoInput::guard_band) the pass runs over the processed rectangle, the viewport
// grown by the band (`frame.size`), and stores only the viewport's pixels, moved to the
// output's origin (`frame.output_offset`, `frame.output_size`): the band's AO is computed
// for the samples beside the viewport and dropped here, with no crop pass to copy the
// viewport out (two thirds of the band's cost on an H200, BENCHMARKS.md). Elsewhere, and
// for passes that write an intermediate texture, pixels are stored where they are.

override CROPS: bool = false;

fn store_output(p: vec2<i32>, ao: f32) {
    var q = p;
    if CROPS {
        q = p - vec2<i32>(frame.output_offset);
        if any(q < vec2<i32>(0)) || any(q >= vec2<i32>(frame.output_size)) {
            return;
        }
    }
    textureStore(ao_out, q, vec4<f32>(ao, 0.0, 0.0, 0.0));
}
