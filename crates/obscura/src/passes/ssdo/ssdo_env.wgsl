// The environment's light for the SSDO passes (src/ssdo.rs): its diffuse irradiance from
// nine spherical harmonics (Ramamoorthi & Hanrahan 2001), normalised by π, and the
// albedo. Mirror: `IrradianceSh::eval` (src/environment.rs).

@group(0) @binding(2) var albedo_in: texture_2d<f32>;
@group(0) @binding(3) var<uniform> ssdo: SsdoUniforms;

// Irradiance / π at view-space unit normal `n`: rotated to world space, then the nine
// harmonics of `sh9_basis` (src/environment.rs), negative lobes clamped to 0.
fn env_irradiance(n: vec3<f32>) -> vec3<f32> {
    let d = ssdo.view_to_world[0].xyz * n.x + ssdo.view_to_world[1].xyz * n.y + ssdo.view_to_world[2].xyz * n.z;
    let y = array<f32, 9>(
        SH9_SCALE[0],
        SH9_SCALE[1] * d.y,
        SH9_SCALE[1] * d.z,
        SH9_SCALE[1] * d.x,
        SH9_SCALE[2] * d.x * d.y,
        SH9_SCALE[2] * d.y * d.z,
        SH9_SCALE[3] * (3.0 * d.z * d.z - 1.0),
        SH9_SCALE[2] * d.x * d.z,
        SH9_SCALE[4] * (d.x * d.x - d.y * d.y),
    );
    var e = vec3<f32>(0.0);
    for (var i = 0u; i < 9u; i++) {
        e += ssdo.irradiance[i].xyz * y[i];
    }
    return max(e, vec3<f32>(0.0));
}

fn albedo_at(q: vec2<i32>) -> vec3<f32> {
    return textureLoad(albedo_in, q, 0).xyz;
}
