// Bent normals through the denoiser (AoOptions::bent_normals): the centre gets its own
// normal plus the fitted offset of its taps' bent normals from their own normals, with the
// AO's weights and the AO's plane fit (per component), renormalised. Filtering the offset
// (the tilt that occlusion gives), not the direction, keeps curved surfaces from being
// flattened: on an unoccluded sphere every offset is zero and the bent normal stays the
// normal, where a mean of the directions leans each pixel toward its neighbours' normals
// (measured on the shared objects: 0.9° → 3.1° from the traced bent normals); the fit, as
// for the AO, keeps a one-sided kernel beside a crease from shifting the tilt. Sky pixels
// pass through. Composed before denoise.wgsl.

@group(0) @binding(4) var bent_in: texture_2d<f32>;
@group(0) @binding(5) var bent_out: texture_storage_2d<rgba32float, write>;

// Weighted sums of the offset o and of o·dx, o·dy; the fitted offset; whether it was fitted.
var<private> bent_sum: vec3<f32>;
var<private> bent_sum_dx: vec3<f32>;
var<private> bent_sum_dy: vec3<f32>;
var<private> bent_offset: vec3<f32>;
var<private> bent_fitted: bool;

fn bent_tap(q: vec2<i32>, w: f32, n: vec3<f32>, d: vec2<f32>) {
    let o = textureLoad(bent_in, q, 0).xyz - n;
    bent_sum += w * o;
    bent_sum_dx += w * d.x * o;
    bent_sum_dy += w * d.y * o;
}

// The plane fit at the centre, with the AO's total weight, mean tap offset `m` and offset
// covariance (xx, yy, xy) (ridge included).
fn bent_fit(total: f32, m: vec2<f32>, cov: vec3<f32>) {
    let mean = bent_sum / total;
    let cx = bent_sum_dx / total - m.x * mean;
    let cy = bent_sum_dy / total - m.y * mean;
    let det = cov.x * cov.y - cov.z * cov.z;
    let gx = (cov.y * cx - cov.z * cy) / det;
    let gy = (cov.x * cy - cov.z * cx) / det;
    bent_offset = mean - gx * m.x - gy * m.y;
    bent_fitted = true;
}

// `n`: the centre's normal.
fn bent_store(p: vec2<i32>, n: vec3<f32>) {
    var b = textureLoad(bent_in, p, 0).xyz;
    let f = n + bent_offset;
    if bent_fitted && dot(f, f) > 1e-12 {
        b = normalize(f);
    }
    textureStore(bent_out, p, vec4<f32>(b, 0.0));
}
