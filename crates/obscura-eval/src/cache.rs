//! On-disk cache of reference images, keyed by everything that determines them: the
//! scene file's bytes, the camera, the resolution and the trace settings (FNV-1a 64).

use crate::{Falloff, PixelSampling, ReferenceAo, TraceSettings};
use obscura_scene::{Camera, CameraProjection};
use std::path::{Path, PathBuf};

/// Bumped whenever the tracer's output for the same inputs changes.
const FORMAT: u32 = 2;
const MAGIC: &[u8; 8] = b"OBSCREF2";

/// FNV-1a, 64-bit.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    pub fn bytes(&mut self, b: &[u8]) -> &mut Self {
        for &x in b {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        self
    }
    pub fn f32s(&mut self, v: &[f32]) -> &mut Self {
        for x in v {
            self.bytes(&x.to_le_bytes());
        }
        self
    }
    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// The cache key of a reference.
pub fn key(scene_bytes: &[u8], cam: &Camera, w: u32, h: u32, s: &TraceSettings) -> u64 {
    let mut f = Fnv::default();
    f.bytes(&FORMAT.to_le_bytes()).bytes(scene_bytes);
    f.f32s(&cam.eye.to_array())
        .f32s(&cam.target.to_array())
        .f32s(&cam.up.to_array());
    f.f32s(&[cam.near, cam.far]);
    match cam.projection {
        CameraProjection::Perspective { fov_y_deg } => f.bytes(b"p").f32s(&[fov_y_deg]),
        CameraProjection::Orthographic { height } => f.bytes(b"o").f32s(&[height]),
    };
    f.bytes(&w.to_le_bytes())
        .bytes(&h.to_le_bytes())
        .f32s(&[s.radius]);
    f.bytes(&s.rays.to_le_bytes()).bytes(match s.falloff {
        Falloff::None => b"n",
        Falloff::Quadratic => b"q",
    });
    // The centre's key is the one from before per-sample references existed.
    if s.sampling == PixelSampling::Msaa4 {
        f.bytes(b"msaa4");
    }
    f.finish()
}

/// Where the reference with `key` lives in `dir`.
pub fn path(dir: &Path, key: u64) -> PathBuf {
    dir.join(format!("ref-{key:016x}.bin"))
}

/// Reads a cached reference; `None` if absent or not a valid file of the right size.
pub fn load(path: &Path, w: u32, h: u32) -> Option<ReferenceAo> {
    let b = std::fs::read(path).ok()?;
    let n = (w * h) as usize;
    if b.len() != 8 + 12 + 20 * n || &b[..8] != MAGIC {
        return None;
    }
    let word = |i: usize| [b[i], b[i + 1], b[i + 2], b[i + 3]];
    if u32::from_le_bytes(word(8)) != w || u32::from_le_bytes(word(12)) != h {
        return None;
    }
    let floats: Vec<f32> = b[20..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    Some(ReferenceAo {
        width: w,
        height: h,
        mean_std_error: f32::from_le_bytes(word(16)),
        ao: floats[..n].to_vec(),
        depth: floats[n..2 * n].to_vec(),
        bent: floats[2 * n..]
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
    })
}

/// Writes a reference atomically (temporary file, then rename).
pub fn store(path: &Path, r: &ReferenceAo) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut b = Vec::with_capacity(20 + 20 * r.ao.len());
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&r.width.to_le_bytes());
    b.extend_from_slice(&r.height.to_le_bytes());
    b.extend_from_slice(&r.mean_std_error.to_le_bytes());
    for v in r.ao.iter().chain(&r.depth).chain(r.bent.iter().flatten()) {
        b.extend_from_slice(&v.to_le_bytes());
    }
    let tmp = path.with_extension(format!("tmp-{}", std::process::id()));
    std::fs::write(&tmp, &b)?;
    std::fs::rename(&tmp, path)
}

const FLOATS_MAGIC: &[u8; 8] = b"OBSFLT01";

/// Reads `count` floats stored by [`store_floats`] for a `w` × `h` image; `None` if
/// absent or not a valid file of that size.
pub fn load_floats(path: &Path, w: u32, h: u32, count: usize) -> Option<Vec<f32>> {
    let b = std::fs::read(path).ok()?;
    if b.len() != 16 + 4 * count || &b[..8] != FLOATS_MAGIC {
        return None;
    }
    let word = |i: usize| u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    if word(8) != w || word(12) != h {
        return None;
    }
    Some(
        b[16..]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect(),
    )
}

/// Writes floats for a `w` × `h` image atomically (temporary file, then rename).
pub fn store_floats(path: &Path, w: u32, h: u32, v: &[f32]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut b = Vec::with_capacity(16 + 4 * v.len());
    b.extend_from_slice(FLOATS_MAGIC);
    b.extend_from_slice(&w.to_le_bytes());
    b.extend_from_slice(&h.to_le_bytes());
    for x in v {
        b.extend_from_slice(&x.to_le_bytes());
    }
    let tmp = path.with_extension(format!("tmp-{}", std::process::id()));
    std::fs::write(&tmp, &b)?;
    std::fs::rename(&tmp, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_round_trip_and_refuse_other_sizes() {
        let dir = std::env::temp_dir().join(format!("obscura-floats-{}", std::process::id()));
        let path = dir.join("f.bin");
        let v = vec![1.0, -2.5, 3.25, 0.0, 7.0, 8.0];
        store_floats(&path, 3, 2, &v).unwrap();
        assert_eq!(load_floats(&path, 3, 2, 6), Some(v));
        assert_eq!(load_floats(&path, 2, 3, 6), None);
        assert_eq!(load_floats(&path, 3, 2, 7), None);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn round_trip_and_key_sensitivity() {
        let r = ReferenceAo {
            width: 3,
            height: 2,
            ao: vec![1.0, 0.5, 0.25, 0.0, 0.75, 1.0],
            depth: vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
            bent: (0..6).map(|i| [i as f32, 0.5, -0.25]).collect(),
            mean_std_error: 0.01,
        };
        let dir = std::env::temp_dir().join(format!("obscura-cache-test-{}", std::process::id()));
        let p = path(&dir, 42);
        store(&p, &r).unwrap();
        let back = load(&p, 3, 2).unwrap();
        assert_eq!(
            (back.ao, back.depth, back.bent, back.mean_std_error),
            (r.ao, r.depth, r.bent, r.mean_std_error)
        );
        assert!(load(&p, 2, 3).is_none(), "size mismatch must not load");
        std::fs::write(&p, b"garbage").unwrap();
        assert!(load(&p, 3, 2).is_none());
        std::fs::remove_dir_all(dir).unwrap();

        let cam = obscura_scene::default_scene::camera();
        let s = TraceSettings {
            radius: 1.0,
            rays: 64,
            falloff: Falloff::None,
            sampling: PixelSampling::Centre,
        };
        let k = key(b"scene", &cam, 8, 8, &s);
        assert_eq!(k, key(b"scene", &cam, 8, 8, &s));
        assert_ne!(k, key(b"scene!", &cam, 8, 8, &s));
        assert_ne!(k, key(b"scene", &cam, 8, 9, &s));
        assert_ne!(
            k,
            key(b"scene", &cam, 8, 8, &TraceSettings { rays: 65, ..s })
        );
        let msaa = TraceSettings {
            sampling: PixelSampling::Msaa4,
            ..s
        };
        assert_ne!(k, key(b"scene", &cam, 8, 8, &msaa));
        let mut moved = cam;
        moved.eye.x += 0.001;
        assert_ne!(k, key(b"scene", &moved, 8, 8, &s));
    }
}
