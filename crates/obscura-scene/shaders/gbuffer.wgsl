// G-buffer rasterization for obscura's CLI, tests and evaluation (not part of the AO
// chain): Depth32Float depth in the standard [0, 1] convention, the geometric view-space
// normal from screen-space derivatives of the view position, so normals agree exactly
// with the depth buffer (no smoothing across facets), and the mesh's linear albedo.

struct Camera {
    view: mat4x4<f32>,
    proj: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) albedo: vec3<f32>,
}

struct FsOut {
    @location(0) normal: vec4<f32>,
    @location(1) albedo: vec4<f32>,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) albedo: vec3<f32>) -> VsOut {
    let v = camera.view * vec4<f32>(position, 1.0);
    var out: VsOut;
    out.clip = camera.proj * v;
    out.view_pos = v.xyz;
    out.albedo = albedo;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> FsOut {
    var n = normalize(cross(dpdx(in.view_pos), dpdy(in.view_pos)));
    // Double-sided: always face the camera (the camera sits at the view-space origin).
    if dot(n, in.view_pos) > 0.0 {
        n = -n;
    }
    return FsOut(vec4<f32>(n, 0.0), vec4<f32>(in.albedo, 1.0));
}
