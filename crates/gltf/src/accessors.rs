//! glTF's mesh data as handrig keeps it for the skin: the top-level `accessors`,
//! `bufferViews`, `buffers`, `meshes` and `skins`, each read leniently (a malformed entry is
//! `None`, a malformed member empty: the skin is a refinement, never a reason to refuse a file),
//! and typed element access into the BIN chunk.

use serde::de::{Deserialize, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::Value as Json;

/// Most entries kept of each of `accessors`, `bufferViews`, `buffers`, `meshes`, `skins` (real
/// avatars: a few thousand accessors at most); entries beyond are ignored, and primitives using
/// them skipped.
pub const MAX_ENTRIES: usize = 65_536;

/// A top-level glTF array read leniently: each entry as [`FromJson`] gives it (`None` when it
/// is malformed), at most [`MAX_ENTRIES`] kept; anything but an array reads as empty.
pub struct List<T>(pub Vec<Option<T>>);

impl<T> Default for List<T> {
    fn default() -> Self {
        List(Vec::new())
    }
}

impl<T> List<T> {
    pub fn get(&self, i: Option<usize>) -> Option<&T> {
        self.0.get(i?)?.as_ref()
    }
}

/// An entry of a [`List`], from its JSON value.
pub trait FromJson: Sized {
    fn from_json(v: &Json) -> Option<Self>;
}

impl<'de, T: FromJson> Deserialize<'de> for List<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> core::result::Result<Self, D::Error> {
        struct Lenient<T>(core::marker::PhantomData<T>);
        impl<'de, T: FromJson> Visitor<'de> for Lenient<T> {
            type Value = List<T>;
            fn expecting(&self, f: &mut core::fmt::Formatter) -> core::fmt::Result {
                f.write_str("any JSON value")
            }
            fn visit_seq<A: SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> core::result::Result<List<T>, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1024));
                while out.len() < MAX_ENTRIES {
                    let Some(v) = seq.next_element::<Json>()? else {
                        return Ok(List(out));
                    };
                    out.push(T::from_json(&v));
                }
                while seq.next_element::<IgnoredAny>()?.is_some() {}
                Ok(List(out))
            }
            fn visit_map<A: MapAccess<'de>>(
                self,
                mut map: A,
            ) -> core::result::Result<List<T>, A::Error> {
                while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
                Ok(List::default())
            }
            fn visit_bool<E>(self, _: bool) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_i64<E>(self, _: i64) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_u64<E>(self, _: u64) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_f64<E>(self, _: f64) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_str<E>(self, _: &str) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_unit<E>(self) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
        }
        d.deserialize_any(Lenient(core::marker::PhantomData))
    }
}

/// A non-negative integer (JSON `3` or `3.0`) small enough to be an index or a byte count.
pub fn uint(v: Option<&Json>) -> Option<usize> {
    let f = v?.as_f64()?;
    (f.fract() == 0.0 && (0.0..9.0e15).contains(&f))
        .then(|| usize::try_from(f as u64).ok())
        .flatten()
}

/// `key` as an index; absent: `default`; present but not an index: `None`.
pub fn uint_or(v: &Json, key: &str, default: usize) -> Option<usize> {
    match v.get(key) {
        None => Some(default),
        some => uint(some),
    }
}

/// `accessors[i]`.
pub struct Accessor {
    pub view: Option<usize>,
    pub offset: usize,
    pub component: u32,
    pub normalized: bool,
    pub count: usize,
    /// Components per element (SCALAR 1 ... MAT4 16).
    pub width: usize,
    pub sparse: bool,
}

impl FromJson for Accessor {
    fn from_json(v: &Json) -> Option<Self> {
        let width = match v.get("type")?.as_str()? {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" | "MAT2" => 4,
            "MAT3" => 9,
            "MAT4" => 16,
            _ => return None,
        };
        Some(Accessor {
            view: match v.get("bufferView") {
                None => None,
                some => Some(uint(some)?),
            },
            offset: uint_or(v, "byteOffset", 0)?,
            component: u32::try_from(uint(v.get("componentType"))?).ok()?,
            normalized: v.get("normalized").and_then(Json::as_bool).unwrap_or(false),
            count: uint(v.get("count"))?,
            width,
            sparse: v.get("sparse").is_some(),
        })
    }
}

/// `bufferViews[i]`.
pub struct View {
    pub buffer: usize,
    pub offset: usize,
    pub length: usize,
    pub stride: Option<usize>,
}

impl FromJson for View {
    fn from_json(v: &Json) -> Option<Self> {
        Some(View {
            buffer: uint(v.get("buffer"))?,
            offset: uint_or(v, "byteOffset", 0)?,
            length: uint(v.get("byteLength"))?,
            stride: match v.get("byteStride") {
                None => None,
                some => Some(uint(some)?),
            },
        })
    }
}

/// `buffers[i]`: only a buffer without `uri` (the GLB's BIN chunk) is read.
pub struct Buffer {
    pub in_glb: bool,
}

impl FromJson for Buffer {
    fn from_json(v: &Json) -> Option<Self> {
        Some(Buffer {
            in_glb: v.get("uri").is_none(),
        })
    }
}

/// A primitive's accessors (`None`: absent or not an index) and mode.
pub struct Primitive {
    pub position: Option<usize>,
    pub joints: Option<usize>,
    pub weights: Option<usize>,
    /// `Some(None)`: not indexed; `None`: an `indices` that is not an index.
    pub indices: Option<Option<usize>>,
    pub mode: Option<usize>,
}

/// `meshes[i]`: its primitives.
pub struct Mesh {
    pub primitives: Vec<Primitive>,
}

impl FromJson for Mesh {
    fn from_json(v: &Json) -> Option<Self> {
        let primitives = v.get("primitives")?.as_array()?;
        Some(Mesh {
            primitives: primitives
                .iter()
                .map(|p| {
                    let attr = |k: &str| uint(p.get("attributes").and_then(|a| a.get(k)));
                    Primitive {
                        position: attr("POSITION"),
                        joints: attr("JOINTS_0"),
                        weights: attr("WEIGHTS_0"),
                        indices: match p.get("indices") {
                            None => Some(None),
                            some => uint(some).map(Some),
                        },
                        mode: uint_or(p, "mode", 4),
                    }
                })
                .collect(),
        })
    }
}

/// `skins[i]`.
pub struct Skin {
    pub joints: Vec<usize>,
    /// `Some(None)`: no inverse bind matrices (identity); `None`: not an index.
    pub inverse_bind: Option<Option<usize>>,
}

impl FromJson for Skin {
    fn from_json(v: &Json) -> Option<Self> {
        let joints = v.get("joints")?.as_array()?;
        Some(Skin {
            joints: joints
                .iter()
                .map(|j| uint(Some(j)))
                .collect::<Option<Vec<_>>>()?,
            inverse_bind: match v.get("inverseBindMatrices") {
                None => Some(None),
                some => uint(some).map(Some),
            },
        })
    }
}

/// The glTF members the skin is read from (a part of [`Document`]).
#[derive(Default)]
pub struct MeshData {
    pub accessors: List<Accessor>,
    pub views: List<View>,
    pub buffers: List<Buffer>,
    pub meshes: List<Mesh>,
    pub skins: List<Skin>,
}

pub const U8: u32 = 5121;
pub const U16: u32 = 5123;
pub const U32: u32 = 5125;
pub const F32: u32 = 5126;

/// An accessor's elements in the BIN chunk, bounds checked once.
pub struct Elements<'a> {
    pub bytes: &'a [u8],
    pub stride: usize,
    pub component: u32,
    pub normalized: bool,
    pub count: usize,
}

impl Elements<'_> {
    /// Component `k` of element `i` (normalized integers in 0..1), or `None` out of bounds
    /// (never for `i < count`, `k < width`: checked in [`MeshData::elements`]).
    pub fn get(&self, i: usize, k: usize) -> Option<f32> {
        let size = component_size(self.component)?;
        let at = i.checked_mul(self.stride)?.checked_add(k * size)?;
        let b = self.bytes.get(at..at + size)?;
        Some(match (self.component, self.normalized) {
            (F32, _) => f32::from_le_bytes(b.try_into().ok()?),
            (U8, false) => f32::from(b[0]),
            (U8, true) => f32::from(b[0]) / 255.0,
            (U16, false) => f32::from(u16::from_le_bytes(b.try_into().ok()?)),
            (U16, true) => f32::from(u16::from_le_bytes(b.try_into().ok()?)) / 65535.0,
            _ => return None,
        })
    }

    /// Element `i` of an integer scalar accessor (indices), exactly.
    pub fn index(&self, i: usize) -> Option<u32> {
        let size = component_size(self.component)?;
        let at = i.checked_mul(self.stride)?;
        let b = self.bytes.get(at..at + size)?;
        Some(match self.component {
            U8 => u32::from(b[0]),
            U16 => u32::from(u16::from_le_bytes(b.try_into().ok()?)),
            U32 => u32::from_le_bytes(b.try_into().ok()?),
            _ => return None,
        })
    }
}

pub fn component_size(c: u32) -> Option<usize> {
    match c {
        5120 | U8 => Some(1),
        5122 | U16 => Some(2),
        U32 | F32 => Some(4),
        _ => None,
    }
}

impl MeshData {
    /// Accessor `i` if it has `width` components of one of `components` (with `normalized`
    /// when given) and lies in the BIN chunk.
    pub fn elements<'a>(
        &self,
        bin: &'a [u8],
        i: Option<usize>,
        width: usize,
        components: &[(u32, Option<bool>)],
    ) -> Option<Elements<'a>> {
        let a = self.accessors.get(i)?;
        if a.sparse || a.width != width {
            return None;
        }
        components
            .iter()
            .find(|(c, n)| *c == a.component && n.is_none_or(|n| n == a.normalized))?;
        let view = self.views.get(a.view)?;
        if !self.buffers.get(Some(view.buffer))?.in_glb || view.buffer != 0 {
            return None;
        }
        let size = component_size(a.component)? * width;
        let stride = view.stride.unwrap_or(size);
        if stride < size || stride > 252 {
            return None;
        }
        let view_end = view.offset.checked_add(view.length)?;
        let bytes = bin.get(view.offset..view_end)?;
        let bytes = bytes.get(a.offset..)?;
        if a.count > 0 {
            let need = (a.count - 1).checked_mul(stride)?.checked_add(size)?;
            if need > bytes.len() {
                return None;
            }
        }
        Some(Elements {
            bytes,
            stride,
            component: a.component,
            normalized: a.normalized,
            count: a.count,
        })
    }
}
