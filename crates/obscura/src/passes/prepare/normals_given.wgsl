// Normals from the caller's texture (composed into prepare.wgsl): signed (normals_mode 1)
// or unorm xyz*0.5+0.5 (normals_mode 2), rotated into view space by frame.normal_to_view
// (identity for view-space normals; the view matrix's rotation for world-space ones).

fn view_normal(p: vec2<i32>, c: vec3<f32>, d: f32) -> vec3<f32> {
    var t = textureLoad(normals_in, p + vec2<i32>(frame.viewport_origin), 0).xyz;
    if frame.normals_mode == 2u {
        t = t * 2.0 - 1.0;
    }
    let r = frame.normal_to_view;
    let n = r[0].xyz * t.x + r[1].xyz * t.y + r[2].xyz * t.z;
    let len2 = dot(n, n);
    if !(len2 > 1e-12) || is_nonfinite(len2) {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    return n * inverseSqrt(len2);
}
