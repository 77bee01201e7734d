//! A minimal wgpu app that draws a lit scene and darkens it with obscura's AO.
//!
//!     cargo run --release -p obscura --example compose -- [out.png] [--guard-band PX] [--second-layer]
//!
//! The app's own part (geometry, a Lambert render pass) is what any renderer already has.
//! The integration is the five steps marked `// obscura, step N` (the crate docs list the
//! same five): depth readable, create once, an AO texture, record per frame, read the AO
//! in lighting (here a compute pass multiplies the lit colour by the AO).
//! Headless: writes a PNG (default `compose.png`) instead of presenting to a window.
//!
//! `--guard-band PX`: the app draws PX pixels beyond each side of the image (a projection
//! widened by the same pixels) and obscura reads them, so boxes just off screen darken the
//! image's edges too (`AoInput::guard_band`; docs/guide/integrate.md, "A guard band").
//!
//! `--second-layer`: the app also peels a second depth layer (the nearest front face at
//! least the thickness prior behind the first) and obscura's bitmask estimator reads it
//! where the first hides it (`AoInput::second_layer`; the guide's "A second depth layer").

use glam::Vec3;
use obscura::{
    Ao, AoInput, AoOptions, AoParams, DepthConvention, GpuContext, Projection, Viewport,
};

const W: u32 = 960;
const H: u32 = 540;

/// Boxes on a floor as (position, normal) triangle vertices.
fn scene() -> Vec<[f32; 6]> {
    let mut v = Vec::new();
    let mut quad = |c: Vec3, u: Vec3, w: Vec3| {
        let n = u.cross(w).normalize();
        for p in [
            c - u - w,
            c + u - w,
            c + u + w,
            c - u - w,
            c + u + w,
            c - u + w,
        ] {
            v.push([p.x, p.y, p.z, n.x, n.y, n.z]);
        }
    };
    quad(Vec3::ZERO, Vec3::Z * 8.0, Vec3::X * 8.0);
    for (x, z, s) in [(-1.5, 0.0, 1.0), (1.2, -0.8, 0.6), (0.2, 1.5, 0.4)] {
        let c = Vec3::new(x, s, z);
        for a in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
            let (b, d) = a.any_orthonormal_pair();
            let (u, w) = if b.cross(d).dot(a) > 0.0 {
                (b, d)
            } else {
                (d, b)
            };
            quad(c + a * s, u * s, w * s);
        }
    }
    v
}

const SHADERS: &str = r#"
@group(0) @binding(0) var<uniform> view_proj: mat4x4<f32>;
struct Out { @builtin(position) pos: vec4<f32>, @location(0) n: vec3<f32> }
@vertex fn vs(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> Out {
    return Out(view_proj * vec4<f32>(p, 1.0), n);
}
@fragment fn fs(i: Out) -> @location(0) vec4<f32> {
    let lit = 0.25 + 0.75 * max(dot(normalize(i.n), normalize(vec3<f32>(0.4, 1.0, 0.3))), 0.0);
    return vec4<f32>(vec3<f32>(0.9, 0.8, 0.7) * lit, 1.0);
}
// Compose: lit colour x AO (the colour GUARD pixels in from its corner, past the band).
override GUARD: u32 = 0u;
@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var ao: texture_2d<f32>;
@group(0) @binding(2) var out: texture_storage_2d<rgba8unorm, write>;
@compute @workgroup_size(8, 8) fn compose(@builtin(global_invocation_id) g: vec3<u32>) {
    if any(g.xy >= textureDimensions(out)) { return; }
    let c = textureLoad(color, g.xy + vec2<u32>(GUARD), 0);
    textureStore(out, g.xy, vec4<f32>(c.rgb * textureLoad(ao, g.xy, 0).x, 1.0));
}
// The second depth layer (--second-layer), a depth peel: a fragment survives only
// SEPARATION (linear view depth) or more behind the first layer at its pixel; front faces
// only (the pipeline culls back faces), the nearest survivor kept by the depth test.
override NEAR: f32 = 0.1;
override FAR: f32 = 50.0;
override SEPARATION: f32 = 0.6;
@group(0) @binding(1) var first: texture_depth_2d;
fn linear(z: f32) -> f32 { return NEAR * FAR / (FAR - z * (FAR - NEAR)); }
@fragment fn peel(i: Out) {
    let z = textureLoad(first, vec2<i32>(i.pos.xy), 0);
    if z >= 1.0 || linear(i.pos.z) < linear(z) + SEPARATION { discard; }
}
"#;

fn target(
    ctx: &GpuContext,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut out_path = "compose.png".to_string();
    let mut guard = 0u32;
    let mut second_layer = false;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--second-layer" {
            second_layer = true;
        } else if a == "--guard-band" {
            let px = args.next().ok_or("--guard-band needs a number of pixels")?;
            guard = px
                .parse()
                .ok()
                .filter(|&g| g <= 1024)
                .ok_or(format!("--guard-band takes 0..=1024 pixels, not `{px}`"))?;
        } else {
            out_path = a;
        }
    }
    // The app's own render targets cover the image and the band around it.
    let drawn = (W + 2 * guard, H + 2 * guard);
    let ctx = GpuContext::new()?; // any wgpu device works; this one prefers a real GPU
    let dev = &ctx.device;
    use wgpu::util::DeviceExt;
    use wgpu::TextureUsages as U;

    // --- The app: camera, geometry, a depth + colour render pass. ---
    let (near, far) = (0.1, 50.0);
    let proj = glam::camera::rh::proj::directx::perspective(1.0, W as f32 / H as f32, near, far);
    let view = glam::camera::rh::view::look_at_mat4(
        Vec3::new(3.0, 3.0, 6.0),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
    );
    // With a band, the app draws with the projection widened by it (same pixel size).
    let widen = Vec3::new(W as f32 / drawn.0 as f32, H as f32 / drawn.1 as f32, 1.0);
    let proj_drawn = glam::Mat4::from_scale(widen) * proj;
    let verts = scene();
    let vbuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&verts),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let ubuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&(proj_drawn * view).to_cols_array()),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(SHADERS.into()),
    });
    let color = target(
        &ctx,
        drawn,
        wgpu::TextureFormat::Rgba8Unorm,
        U::RENDER_ATTACHMENT | U::TEXTURE_BINDING,
    );
    // obscura, step 1: obscura reads the depth buffer: give it TEXTURE_BINDING usage.
    let depth = target(
        &ctx,
        drawn,
        wgpu::TextureFormat::Depth32Float,
        U::RENDER_ATTACHMENT | U::TEXTURE_BINDING,
    );
    // With --second-layer, the peeled layer: a second depth target of the same kind.
    let second = target(
        &ctx,
        drawn,
        wgpu::TextureFormat::Depth32Float,
        U::RENDER_ATTACHMENT | U::TEXTURE_BINDING,
    );
    let (color_view, depth_view, second_view) = (
        color.create_view(&Default::default()),
        depth.create_view(&Default::default()),
        second.create_view(&Default::default()),
    );
    let params = AoParams {
        radius: 0.6,
        ..Default::default()
    };
    // The lit pass, and the peel: depth only, front faces, the fragment stage discarding.
    let pipeline = |peel: bool| {
        let constants = [
            ("NEAR", near as f64),
            ("FAR", far as f64),
            ("SEPARATION", (params.thickness * params.radius) as f64),
        ];
        let targets = [Some(wgpu::TextureFormat::Rgba8Unorm.into())];
        dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: None,
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 24,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
                })],
                compilation_options: Default::default(),
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(if peel { "peel" } else { "fs" }),
                targets: if peel { &[] } else { &targets },
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: if peel { &constants } else { &[] },
                    ..Default::default()
                },
            }),
            primitive: wgpu::PrimitiveState {
                cull_mode: peel.then_some(wgpu::Face::Back),
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        })
    };
    let (draw, peel) = (pipeline(false), pipeline(true));
    let draw_bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &draw.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: ubuf.as_entire_binding(),
        }],
    });
    let peel_bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &peel.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: ubuf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&depth_view),
            },
        ],
    });

    // obscura, step 2: once, at start-up: compile the passes, describe the camera. (A
    // second layer is read by the bitmask estimator.)
    let options = if second_layer {
        AoOptions {
            estimator: obscura::Estimator::Bitmask,
            second_layer: true,
            ..AoOptions::default()
        }
    } else {
        AoOptions::default()
    };
    let mut ao = Ao::new(dev, options)?;
    let projection = Projection::from_matrix(proj.to_cols_array_2d(), DepthConvention::Standard)?;
    // obscura, step 3: an R32Float AO texture the app owns (STORAGE_BINDING for obscura,
    // TEXTURE_BINDING for lighting), so the lighting bind group is made once.
    let ao_tex = target(
        &ctx,
        (W, H),
        wgpu::TextureFormat::R32Float,
        U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
    );
    let ao_view = ao_tex.create_view(&Default::default());
    let composed = target(
        &ctx,
        (W, H),
        wgpu::TextureFormat::Rgba8Unorm,
        U::STORAGE_BINDING | U::COPY_SRC,
    );
    let compose = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("compose"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &[("GUARD", guard as f64)],
            ..Default::default()
        },
        cache: None,
    });
    let composed_view = composed.create_view(&Default::default());
    let compose_bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &compose.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&color_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&ao_view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&composed_view),
            },
        ],
    });

    // --- One frame. ---
    ctx.run(|enc| {
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_pipeline(&draw);
            pass.set_bind_group(0, &draw_bind, &[]);
            pass.set_vertex_buffer(0, vbuf.slice(..));
            pass.draw(0..verts.len() as u32, 0..1);
        }
        if second_layer {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &second_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_pipeline(&peel);
            pass.set_bind_group(0, &peel_bind, &[]);
            pass.set_vertex_buffer(0, vbuf.slice(..));
            pass.draw(0..verts.len() as u32, 0..1);
        }
        // obscura, step 4: per frame, into the same encoder, after the depth is written.
        let input = AoInput {
            depth: &depth_view,
            convention: DepthConvention::Standard,
            projection,
            normals: None,
            // The image inside the band (the band's depth is read, not output); the
            // projection stays the image's own.
            viewport: Some(Viewport {
                x: guard,
                y: guard,
                width: W,
                height: H,
            }),
            guard_band: guard,
            second_layer: second_layer.then_some(&second_view),
            output: Some(&ao_view),
        };
        ao.record(dev, &ctx.queue, enc, &input, &params)?;
        // obscura, step 5: lighting reads the AO (1 = unoccluded); here lit colour x AO.
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&compose);
        pass.set_bind_group(0, &compose_bind, &[]);
        pass.dispatch_workgroups(W.div_ceil(8), H.div_ceil(8), 1);
        Ok(())
    })?;

    // A check, so CI notices a broken integration: the boxes must darken the floor
    // around their bases, and AO stays in [0, 1].
    let values = ctx.read_f32(&ao_tex)?;
    let dark = values.iter().filter(|&&a| a < 0.8).count();
    if dark * 200 < values.len() || values.iter().any(|a| !(0.0..=1.0).contains(a)) {
        return Err(format!(
            "implausible AO: {dark} of {} pixels below 0.8",
            values.len()
        )
        .into());
    }
    let pixels = ctx.read_texture(&composed)?;
    image::save_buffer(&out_path, &pixels, W, H, image::ExtendedColorType::Rgba8)?;
    eprintln!(
        "wrote {out_path} ({}, AO {:?})",
        ctx.describe(),
        ao.options().estimator
    );
    Ok(())
}
