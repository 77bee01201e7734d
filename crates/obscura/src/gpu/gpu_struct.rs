//! One source of truth for structs shared by Rust and WGSL: [`gpu_struct!`] declares a
//! `#[repr(C)]` Pod struct and generates its WGSL declaration from the same field list, so
//! no layout is ever typed twice. A naga test checks the generated offsets (tests/gpu/shaders.rs).

/// The WGSL spelling of a Rust field type used in a [`gpu_struct!`].
pub trait WgslType {
    const WGSL: &'static str;
}

macro_rules! wgsl_types {
    ($($t:ty => $s:expr),* $(,)?) => { $(impl WgslType for $t { const WGSL: &'static str = $s; })* };
}
wgsl_types! {
    f32 => "f32",
    u32 => "u32",
    i32 => "i32",
    [f32; 2] => "vec2<f32>",
    [u32; 2] => "vec2<u32>",
    [f32; 4] => "vec4<f32>",
    [u32; 4] => "vec4<u32>",
    [[f32; 4]; 3] => "array<vec4<f32>, 3>",
    [[f32; 4]; 4] => "mat4x4<f32>",
    [[f32; 4]; 9] => "array<vec4<f32>, 9>",
    [[f32; 4]; crate::passes::jitter::PATTERN_COUNT] => "array<vec4<f32>, PATTERN_COUNT>",
}

/// Declares a struct usable as a uniform, with `fn wgsl() -> String` giving its WGSL form.
/// Field order must respect WGSL alignment (vec2 → 8, vec4/arrays → 16); the layout test
/// in tests/gpu/shaders.rs fails otherwise.
#[macro_export]
#[doc(hidden)]
macro_rules! gpu_struct {
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $field:ident : $ty:ty,)* }) => {
        $(#[$m])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name { $($(#[$fm])* pub $field: $ty,)* }

        impl $name {
            /// The WGSL declaration of this struct.
            pub fn wgsl() -> String {
                let mut s = format!("struct {} {{\n", stringify!($name));
                $(s.push_str(&format!(
                    "    {}: {},\n",
                    stringify!($field),
                    <$ty as $crate::gpu::gpu_struct::WgslType>::WGSL
                ));)*
                s.push_str("}\n");
                s
            }

            /// `(field name, byte offset)` of each field in Rust's layout.
            pub fn field_offsets() -> Vec<(&'static str, usize)> {
                vec![$((stringify!($field), std::mem::offset_of!($name, $field)),)*]
            }
        }
    };
}
