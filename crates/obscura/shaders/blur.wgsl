// Depth-aware separable blur at the AO's working resolution: 9 taps along one axis
// (VERTICAL picks which), Gaussian weights BLUR_WEIGHTS (sigma = 2 pixels), each times
// exp(-(distance from the centre's tangent plane / (PLANE_TOLERANCE x depth))^2), so AO
// does not cross depth edges (edge-stopping on view-space depth). Sky taps are skipped.
// CPU mirror: src/reference.rs, `blur`.

override VERTICAL: bool = false;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var prepared_in: texture_2d<f32>;
@group(0) @binding(2) var ao_in: texture_2d<f32>;
@group(0) @binding(3) var ao_out: texture_storage_2d<r32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let centre = textureLoad(prepared_in, p, 0);
    var ao = textureLoad(ao_in, p, 0).x;
    if centre.x > 0.0 {
        let pos = view_position(vec2<f32>(p) + 0.5, centre.x);
        let axis = select(vec2<i32>(1, 0), vec2<i32>(0, 1), VERTICAL);
        var sum = ao;
        var total = 1.0;
        for (var k = -4; k <= 4; k++) {
            let q = p + axis * k;
            if k == 0 || any(q < vec2<i32>(0)) || any(q >= vec2<i32>(frame.size)) {
                continue;
            }
            let s = textureLoad(prepared_in, q, 0);
            if s.x <= 0.0 {
                continue;
            }
            let z = abs(dot(view_position(vec2<f32>(q) + 0.5, s.x) - pos, centre.yzw)) / (PLANE_TOLERANCE * centre.x);
            let w = BLUR_WEIGHTS[abs(k)] * exp(-z * z);
            sum += w * textureLoad(ao_in, q, 0).x;
            total += w;
        }
        ao = sum / total;
    }
    textureStore(ao_out, p, vec4<f32>(ao, 0.0, 0.0, 0.0));
}
