// The demo page's display pass (crates/obscura-web): a full-screen triangle that shows the
// AO, the scene lit with it, or the AO beside depth and normals. Reads the G-buffer
// (obscura-scene) and obscura's output texel by texel.

struct View {
    // 0: AO; 1: lit (albedo × (ambient × AO + sun)); 2: AO | depth | normals in thirds.
    mode: u32,
    width: u32,
    // The camera's clip planes, to linearise the G-buffer's reversed-Z depth.
    near: f32,
    far: f32,
    // The G-buffer's guard band: the view's pixel q is its texel q + guard (the AO is the
    // view's own size).
    guard: u32,
}

@group(0) @binding(0) var ao: texture_2d<f32>;
@group(0) @binding(1) var normals: texture_2d<f32>;
@group(0) @binding(2) var depth: texture_depth_2d;
@group(0) @binding(3) var albedo: texture_2d<f32>;
@group(0) @binding(4) var<uniform> view: View;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let q = vec2<i32>(p.xy);
    let a = textureLoad(ao, q, 0).x;
    let gq = q + vec2<i32>(i32(view.guard));
    let n = textureLoad(normals, gq, 0).xyz;
    let z = textureLoad(depth, gq, 0);
    let base = textureLoad(albedo, gq, 0);
    if view.mode == 1u {
        if base.a == 0.0 {
            return vec4<f32>(0.62, 0.74, 0.88, 1.0);
        }
        // View-space sun from the upper left, behind the camera.
        let sun = max(dot(normalize(n), normalize(vec3<f32>(-0.4, 0.8, 0.45))), 0.0);
        let lit = base.rgb * (0.55 * a + 0.6 * sun * (0.5 + 0.5 * a));
        return vec4<f32>(lit, 1.0);
    }
    if view.mode == 2u {
        let third = i32(view.width / 3u);
        if q.x >= 2 * third {
            return vec4<f32>(n * 0.5 + 0.5, 1.0);
        }
        if q.x >= third {
            // Linear depth, near white, 20 units black.
            let lin = view.near * view.far / (view.near + z * (view.far - view.near));
            let d = select(1.0 - min(lin / 20.0, 1.0), 0.0, z <= 0.0);
            return vec4<f32>(vec3<f32>(d), 1.0);
        }
    }
    return vec4<f32>(vec3<f32>(a), 1.0);
}
