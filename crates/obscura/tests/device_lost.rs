//! A lost device (here destroyed on purpose) surfaces as typed errors from every entry
//! point, never a panic. Its own binary: it destroys its device.

use obscura::{
    AdapterChoice, Ao, AoInput, AoOptions, AoParams, DepthConvention, Error, GpuContext, Projection,
};

#[test]
fn a_lost_device_gives_typed_errors() {
    let c = GpuContext::with_choice(&AdapterChoice::from_env())
        .unwrap_or_else(|e| panic!("this test needs a Vulkan adapter (lavapipe is enough): {e}"));
    let (w, h) = (16u32, 16u32);
    let tex = c.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("depth"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let view = tex.create_view(&Default::default());
    let input = AoInput {
        depth: &view,
        convention: DepthConvention::LinearView,
        projection: Projection::Perspective {
            fov_y: 1.0,
            aspect: 1.0,
            near: 0.1,
            far: 50.0,
        },
        normals: None,
        viewport: None,
        output: None,
    };
    let params = AoParams::default();
    let mut ao = Ao::new(&c.device, AoOptions::default()).unwrap();
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();

    c.device.destroy();
    let typed = |what: &str, e: Error| {
        assert!(
            matches!(
                e,
                Error::DeviceLost(_) | Error::Gpu(_) | Error::OutOfMemory(_)
            ),
            "{what}: {e:?}"
        );
    };
    // A frame on the lost device.
    match c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params)) {
        Ok(()) => panic!("recording on a destroyed device succeeded"),
        Err(e) => typed("record", e),
    }
    // Creation on it, and a resize (new textures).
    if let Err(e) = Ao::new(&c.device, AoOptions::default()) {
        typed("Ao::new", e);
    }
    let small = AoInput {
        viewport: Some(obscura::Viewport {
            x: 0,
            y: 0,
            width: 8,
            height: 8,
        }),
        ..input
    };
    match c.run(|enc| ao.record(&c.device, &c.queue, enc, &small, &params)) {
        Ok(()) => panic!("a resize on a destroyed device succeeded"),
        Err(e) => typed("resize", e),
    }
    match c.read_f32(&tex) {
        Ok(_) => panic!("reading back from a destroyed device succeeded"),
        Err(e) => typed("read-back", e),
    }
}
