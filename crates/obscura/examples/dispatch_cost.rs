//! What one compute pass costs on this adapter, apart from the work of obscura's shaders:
//! an empty dispatch over every pixel, then a store, one texel load and nine loads per
//! pixel, and one load with 1024 multiply-adds or 256 special-function operations (square
//! roots and divisions) after it. Each is timed as 1 pass, as 4 passes, and as 4 dispatches
//! in one pass; the rates per fetch and per operation that follow are the adapter's peaks
//! in the cost model's roofline (obscura::frame::cost).
//!
//!     cargo run --release -p obscura --example dispatch_cost -- [WIDTHxHEIGHT]
//!
//! (default 640x400).
//!
//! The question it answers (BENCHMARKS.md, "What a pass costs on lavapipe"): is a pass's
//! fixed cost the dispatch machinery, which fusing passes would save, or the work every
//! invocation does? Wall clock around submit + wait, median of 25 submissions, two rounds.
//! The probes' WGSL is generated here: they are measurements, not passes of the library.

use obscura::GpuContext;
use std::time::Instant;

const RUNS: usize = 25;

/// A probe: `body` runs once per pixel with `p` (the pixel) in scope, `src` to read and
/// `dst` to write.
fn probe_source(body: &str, width: u32, height: u32) -> String {
    format!(
        "@group(0) @binding(0) var src: texture_2d<f32>;\n\
         @group(0) @binding(1) var dst: texture_storage_2d<rgba32float, write>;\n\
         @compute @workgroup_size(8, 8, 1)\n\
         fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{\n\
             if gid.x >= {width}u || gid.y >= {height}u {{ return; }}\n\
             let p = vec2<i32>(gid.xy);\n\
             {body}\n\
         }}\n"
    )
}

/// Nine loads (the 3 × 3 neighbourhood, clamped to the image) summed and stored, written
/// out so no loop counter is timed with them.
fn nine_loads(width: u32, height: u32) -> String {
    let mut s = String::from("var a = vec4<f32>(0.0);\n");
    for dy in -1..=1 {
        for dx in -1..=1 {
            s += &format!(
                "a += textureLoad(src, clamp(p + vec2<i32>({dx}, {dy}), vec2<i32>(0), \
                 vec2<i32>({}, {})), 0);\n",
                width - 1,
                height - 1
            );
        }
    }
    s + "textureStore(dst, p, a);"
}

/// One load, then `ops` operations per pixel in four independent lanes (a vec4), unrolled,
/// stored: `op` maps `a` to its next value.
fn arithmetic(ops: u32, op: &str) -> String {
    let mut s = String::from("var a = textureLoad(src, p, 0);\n");
    for _ in 0..ops / 4 {
        s += &format!("a = {op};\n");
    }
    s + "textureStore(dst, p, a);"
}

/// Operations per pixel in the arithmetic probes.
const ALU_OPS: u32 = 1024;
const SPECIAL_OPS: u32 = 256;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() > 1 {
        return Err(format!("expected at most one argument, WIDTHxHEIGHT; got {args:?}").into());
    }
    let size = args.first().map_or("640x400", String::as_str);
    let (width, height) = size
        .split_once(['x', '×'])
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| w > 0 && h > 0)
        .ok_or_else(|| format!("size `{size}`: expected WIDTHxHEIGHT, each at least 1"))?;
    let ctx = GpuContext::new()?;
    let max = ctx.device.limits().max_texture_dimension_2d;
    if width > max || height > max {
        return Err(
            format!("size `{size}`: this adapter's textures are at most {max} on a side").into(),
        );
    }
    println!("{}, {width}×{height}", ctx.describe());
    let dev = &ctx.device;
    let texture = |usage| {
        dev.create_texture(&wgpu::TextureDescriptor {
            label: Some("dispatch_cost"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage,
            view_formats: &[],
        })
    };
    let src = texture(wgpu::TextureUsages::TEXTURE_BINDING);
    let dst = texture(wgpu::TextureUsages::STORAGE_BINDING);
    let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("dispatch_cost"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: wgpu::TextureFormat::Rgba32Float,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            },
        ],
    });
    let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("dispatch_cost"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&src.create_view(&Default::default())),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&dst.create_view(&Default::default())),
            },
        ],
    });
    let pipeline_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("dispatch_cost"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let probes = [
        ("empty", String::new()),
        ("store", "textureStore(dst, p, vec4<f32>(1.0));".into()),
        (
            "1 load + store",
            "textureStore(dst, p, textureLoad(src, p, 0));".into(),
        ),
        ("9 loads + store", nine_loads(width, height)),
        (
            "1 load, 1024 multiply-adds, store",
            arithmetic(ALU_OPS, "fma(a, vec4<f32>(0.999), vec4<f32>(0.001))"),
        ),
        (
            "1 load, 256 sqrt or divisions, store",
            // Per lane: a square root, a division and two adds.
            arithmetic(SPECIAL_OPS / 2, "sqrt(a) + 1.0 / (a + vec4<f32>(1.5))"),
        ),
    ];
    let pipelines: Vec<(&str, wgpu::ComputePipeline)> = probes
        .iter()
        .map(|(name, body)| {
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(probe_source(body, width, height).into()),
            });
            let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
            (*name, pipeline)
        })
        .collect();
    // Creation errors go to the context's error sink: report them here, not at the first
    // submission.
    ctx.take_errors()
        .map_err(|e| format!("creating the probes' textures and pipelines: {e}"))?;
    let groups = (width.div_ceil(8), height.div_ceil(8));
    // `dispatches` dispatches, each in a pass of its own or all in one pass.
    let time = |pipeline: &wgpu::ComputePipeline, dispatches: usize, own_pass: bool| {
        let mut ms = Vec::with_capacity(RUNS);
        for _ in 0..RUNS {
            let start = Instant::now();
            ctx.run(|encoder| {
                let (passes, per_pass) = if own_pass {
                    (dispatches, 1)
                } else {
                    (1, dispatches)
                };
                for _ in 0..passes {
                    let mut pass = encoder.begin_compute_pass(&Default::default());
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, &bind, &[]);
                    for _ in 0..per_pass {
                        pass.dispatch_workgroups(groups.0, groups.1, 1);
                    }
                }
                Ok(())
            })?;
            ms.push(start.elapsed().as_secs_f64() * 1e3);
        }
        Ok::<f64, obscura::Error>(median(ms))
    };
    let mut submit = Vec::with_capacity(RUNS);
    for _ in 0..RUNS {
        let start = Instant::now();
        ctx.run(|_| Ok(()))?;
        submit.push(start.elapsed().as_secs_f64() * 1e3);
    }
    println!("an empty submission: {:.3} ms", median(submit));
    println!("| round | probe | 1 pass, ms | 4 passes, ms | per extra pass, ms | 4 dispatches in 1 pass, ms |");
    println!("|---|---|---|---|---|---|");
    let mut rates = Vec::new();
    for round in 1..=2 {
        let mut per_pass = Vec::new();
        for (name, pipeline) in &pipelines {
            let one = time(pipeline, 1, true)?;
            let four = time(pipeline, 4, true)?;
            let fused = time(pipeline, 4, false)?;
            per_pass.push((four - one) / 3.0);
            println!(
                "| {round} | {name} | {one:.2} | {four:.2} | {:.2} | {fused:.2} |",
                (four - one) / 3.0
            );
        }
        // Per extra pass (no submission in it): the probes' differences from one load.
        let pixels = width as f64 * height as f64;
        let ns = |probe: usize| (per_pass[probe] - per_pass[2]) * 1e6 / pixels;
        let alu = ns(4) / ALU_OPS as f64;
        let special = (ns(5) - alu * SPECIAL_OPS as f64) / SPECIAL_OPS as f64;
        rates.push((ns(3) / 8.0, alu, special));
    }
    for (round, (fetch, alu, special)) in rates.iter().enumerate() {
        println!(
            "round {}, per pixel of an extra pass: {fetch:.3} ns a fetch, {alu:.4} ns an \
             operation, {special:.4} ns a special operation",
            round + 1
        );
    }
    Ok(())
}
