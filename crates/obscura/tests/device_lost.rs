//! A lost device (here destroyed on purpose) surfaces as typed errors from every entry
//! point, never a panic. Its own binary: it destroys its device.

use obscura::{Ao, AoInput, AoOptions, AoParams, Error, Projection};

mod common;

#[test]
fn a_lost_device_gives_typed_errors() {
    let c = common::context(None);
    let (w, h) = (16u32, 16u32);
    let tex = common::upload_r32(&c, &vec![2.0; (w * h) as usize], w, h);
    let view = tex.create_view(&Default::default());
    let input = common::linear_input(
        &view,
        Projection::Perspective {
            fov_y: 1.0,
            aspect: 1.0,
            near: 0.1,
            far: 50.0,
        },
    );
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
