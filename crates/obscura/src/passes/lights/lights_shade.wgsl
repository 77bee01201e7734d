// Many-light diffuse shading, every light or an interleaved subset per pixel (Segovia,
// Iehl, Mitanchey & Péroche 2006, "Non-interleaved Deferred Shading of Interleaved Sample
// Patterns"; seed 000's interleaved sampling). Composed after prepared_full.wgsl (or
// prepared_layers.wgsl) and an output: lit_out_plain.wgsl, or lit_out_packed.wgsl when a
// merge follows.
//
// With PERIOD n > 1, pixel p shades only the lights whose index is congruent to its layer
// (common.wgsl, `layer_of`) modulo n², scaled by n²: each pixel class of an n × n tile
// shades a different 1/n² of the lights, and lights_merge.wgsl sums the classes back over
// one tile, guided by geometry. PERIOD 1 shades every light at every pixel.
//
// Each light: Lambert's cosine, inverse-square falloff windowed to zero at the light's
// range, (1 − (d/range)⁴)² (Karis 2013, "Real Shading in Unreal Engine 4"), and the
// distance clamped below at LIGHT_MIN_DISTANCE × range, the usual clamp of virtual point
// lights' singularity (Keller 1997, "Instant Radiosity"). No visibility: the output is the
// unshadowed irradiance E (albedo 1), rgb; sky pixels are 0.
// CPU mirror: src/reference.rs, `shade_lights`.

override PERIOD: u32 = 1u;
// Dispatch over the deinterleaved layout: workgroup layer gid.z covers class gid.z's
// lattice (pixel = texel × PERIOD + the class's offset), so every invocation of a
// workgroup walks the same lights, in step (Segovia et al.'s non-interleaved shading of
// interleaved patterns: coherent light reads). Off: the pixel grid, classes side by side.
override LAYERED: bool = false;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
// A uniform array, not a storage buffer: every invocation reads the same few lights in
// turn, which is what uniform (constant) buffers serve; on lavapipe every-light shading
// ran 10.7× faster so (BENCHMARKS.md, "Many-light shading"). Hence at most LIGHTS_MAX.
@group(0) @binding(2) var<uniform> lights: array<GpuLight, LIGHTS_MAX>;
@group(0) @binding(3) var<uniform> shade: LightsUniforms;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    var pixel = gid.xy;
    var first = layer_of(gid.xy, PERIOD);
    if LAYERED {
        first = gid.z;
        pixel = gid.xy * PERIOD + vec2<u32>(first % PERIOD, first / PERIOD);
    }
    if any(pixel >= frame.size) {
        return;
    }
    let p = vec2<i32>(pixel);
    let centre = prepared_at(p);
    var e = vec3<f32>(0.0);
    if centre.x > 0.0 {
        let pos = view_position(vec2<f32>(p) + 0.5, centre.x);
        let n = centre.yzw;
        let stride = PERIOD * PERIOD;
        // Lights first, first + stride, ... below the count.
        let taken = (shade.count + stride - 1u - min(first, shade.count)) / stride;
        for (var k = 0u; k < taken; k++) {
            let light = lights[first + k * stride];
            let v = light.position_inv_range2.xyz - pos;
            let d2 = dot(v, v);
            let x = d2 * light.position_inv_range2.w;
            let window = saturate(1.0 - x * x);
            let cosine = max(dot(n, v), 0.0) * inverseSqrt(max(d2, 1e-30));
            e += light.colour_min_distance2.xyz * (cosine * window * window / max(d2, light.colour_min_distance2.w));
        }
        e *= f32(stride);
    }
    store_lit(p, centre, e);
}
