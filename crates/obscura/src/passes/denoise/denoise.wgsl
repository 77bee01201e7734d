// Edge-aware spatial denoiser at the AO's working resolution: one pass of a joint
// bilateral filter (Tomasi & Manduchi 1998; Kopf et al. 2007, "Joint Bilateral
// Upsampling") guided by depth and normals, in the spirit of XeGTAO's denoiser (a small
// kernel over the noise period). Composed after prepared_full.wgsl or prepared_layers.wgsl
// and merge.wgsl.
//
// The kernel spans exactly one period of the sampling patterns (PERIOD 2: 3×3, PERIOD 4:
// 5×5) with spatial weights 1-2-1 or 1-2-2-2-1 per axis: the two end taps share a residue
// modulo the period, so every pattern of the tile gets the same total weight and the
// dither cancels on a flat surface (seed 003's tent filter has the same property for 2).
// Each tap is further weighted by its plane and normal weights (merge.wgsl), with the
// plane tolerance min(PLANE_TOLERANCE x depth, DENOISE_RADIUS_TOLERANCE x radius), at
// least NOISE_TOLERANCE_SIGMAS x σ of the depth noise: AO changes over the scale of the AO
// radius, so points farther apart than a fraction of it across the surface do not share AO.
// The output is not the weighted mean but the value at the centre of the weighted
// least-squares plane through the taps, ao ≈ a + g·(dx, dy) (local linear regression,
// Cleveland 1979; the joint bilateral filter's bias at edges and its removal: Buades,
// Coll & Morel 2006). Where the kernel is symmetric (flat interiors) the two agree. Where
// a crease or an edge rejects one side, the mean of the remaining taps is biased by the
// AO gradient, which is steepest exactly there (a concave crease darkens within a pixel
// or two), and the fit removes that bias. A ridge of DENOISE_RIDGE px² on the slope
// makes taps along one line give slope 0 across it, not 0/0.
// At the image border the taps are mirrored, not dropped: a one-sided kernel there would
// extrapolate the slope across the border from noise alone (the edge pixel has no taps
// beyond it, unlike a crease, where the other side exists but is another surface).
// Sky taps are skipped; sky pixels pass through. Bent normals, when on, get the same fit
// of their offsets from the taps' normals (denoise_bent.wgsl). A tap's AO and prepared
// value come in one fetch: the pass before (the AO pass or the temporal pass) stores them
// packed (estimators/ao_packed.wgsl), half the fetches of reading the two apart. CPU
// mirror: src/reference.rs, `denoise`.

override PERIOD: u32 = 2u;

// A tap: its prepared value vec4(linear depth, normal) and its AO.
struct DenoiseTap {
    prepared: vec4<f32>,
    ao: f32,
}

fn denoise_tap(q: vec2<i32>) -> DenoiseTap {
    let t = textureLoad(ao_in, q, 0);
    return DenoiseTap(unpack_prepared(t), abs(t.w) - 1.0);
}

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(2) var ao_in: texture_2d<f32>;
@group(0) @binding(3) var ao_out: texture_storage_2d<r32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let own = denoise_tap(p);
    let centre = own.prepared;
    var ao = own.ao;
    if centre.x > 0.0 {
        let pos = view_position(vec2<f32>(p) + 0.5, centre.x);
        let n = centre.yzw;
        let inv_tol = 1.0 / max(
            min(PLANE_TOLERANCE * centre.x, DENOISE_RADIUS_TOLERANCE * frame.radius),
            NOISE_TOLERANCE_SIGMAS * depth_sigma(centre.x),
        );
        let r = i32(PERIOD / 2u);
        let size = vec2<i32>(frame.size);
        // Weighted sums of 1, v, d, v·d and d⊗d, d = (dx, dy) the tap's offset.
        var total = 0.0;
        var sum = 0.0;
        var sum_d = vec2<f32>(0.0);
        var sum_vd = vec2<f32>(0.0);
        var sum_dd = vec3<f32>(0.0);
        for (var dy = -r; dy <= r; dy++) {
            for (var dx = -r; dx <= r; dx++) {
                // Taps past the image border are mirrored back into it (whole-sample
                // symmetric extension), so the kernel stays symmetric across the border and
                // the fit does not extrapolate a one-sided slope onto the edge pixel.
                var q = p + vec2<i32>(dx, dy);
                q = select(q, -q, q < vec2<i32>(0));
                q = clamp(select(q, 2 * (size - 1) - q, q >= size), vec2<i32>(0), size - 1);
                let tap = denoise_tap(q);
                let s = tap.prepared;
                if s.x <= 0.0 {
                    continue;
                }
                let spatial = select(2.0, 1.0, abs(dx) == r) * select(2.0, 1.0, abs(dy) == r);
                let w = spatial * merge_weight(pos, n, inv_tol, q, s);
                let v = tap.ao;
                let d = vec2<f32>(f32(dx), f32(dy));
                total += w;
                sum += w * v;
                sum_d += w * d;
                sum_vd += w * v * d;
                sum_dd += w * vec3<f32>(d.x * d.x, d.y * d.y, d.x * d.y);
                bent_tap(q, w, s.yzw, d);
            }
        }
        // Centred moments: mean offset m, covariance of offsets (xx, yy, xy), covariance of
        // offsets with values c; slope g = cov⁻¹ c; the plane's value at the centre.
        let mean = sum / total;
        let m = sum_d / total;
        let xx = sum_dd.x / total - m.x * m.x + DENOISE_RIDGE;
        let yy = sum_dd.y / total - m.y * m.y + DENOISE_RIDGE;
        let xy = sum_dd.z / total - m.x * m.y;
        let c = sum_vd / total - m * mean;
        let g = vec2<f32>(yy * c.x - xy * c.y, xx * c.y - xy * c.x) / (xx * yy - xy * xy);
        ao = clamp(mean - dot(g, m), 0.0, 1.0);
        bent_fit(total, m, vec3<f32>(xx, yy, xy));
    }
    store_output(p, ao);
    bent_store(p, centre.yzw);
}
