//! The GLB container (glTF 2.0 binary): the 12-byte header, the JSON chunk and the optional BIN
//! chunk, checked for magic, version, lengths and alignment. Every malformed input is an
//! [`Error::Vrm`] naming the part of the file and the problem; nothing here panics whatever the
//! bytes.

use crate::error::{Error, Result};

/// Largest JSON chunk read (real avatars: a few MB).
pub const MAX_JSON_BYTES: usize = 64 << 20;

pub const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF", little-endian
pub const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
pub const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
pub const HEADER_LEN: usize = 12;
pub const CHUNK_HEADER_LEN: usize = 8;

/// The JSON chunk of a GLB, borrowed from the input, and where the BIN chunk is (its data is
/// read only for the skin).
pub struct Glb<'a> {
    pub json: &'a [u8],
    /// The BIN chunk's byte range, empty when there is none.
    pub bin: core::ops::Range<usize>,
}

pub fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let end = at.checked_add(4)?;
    let b: [u8; 4] = bytes.get(at..end)?.try_into().ok()?;
    Some(u32::from_le_bytes(b))
}

/// Shows four bytes as text when they are printable, else as hex, for error messages.
pub fn show_tag(tag: u32) -> String {
    let b = tag.to_le_bytes();
    if b.iter().all(|c| c.is_ascii_graphic() || *c == b' ') {
        format!("\"{}\"", String::from_utf8_lossy(&b))
    } else {
        format!("0x{tag:08X}")
    }
}

impl<'a> Glb<'a> {
    pub fn parse(bytes: &'a [u8]) -> Result<Self> {
        let got = bytes.len();
        if let Some(magic) = read_u32(bytes, 0) {
            if magic != GLB_MAGIC {
                let hint = if bytes.first() == Some(&b'{') {
                    " (this looks like a JSON .gltf; a .vrm is the binary form)"
                } else {
                    ""
                };
                return Err(Error::vrm(format!(
                    "not a glTF binary (magic {}, expected \"glTF\"){hint}",
                    show_tag(magic)
                )));
            }
        }
        let (Some(version), Some(length)) = (read_u32(bytes, 4), read_u32(bytes, 8)) else {
            return Err(Error::vrm(format!(
                "truncated: {got} bytes, shorter than the {HEADER_LEN}-byte GLB header"
            )));
        };
        if version != 2 {
            return Err(Error::vrm(format!(
                "unsupported glTF binary version {version} (expected 2)"
            )));
        }
        let length = length as usize;
        if length > got {
            return Err(Error::vrm(format!(
                "truncated: header says {length} bytes, got {got}"
            )));
        }
        if length < got {
            return Err(Error::vrm(format!(
                "header says {length} bytes, got {got} (trailing data after the GLB)"
            )));
        }
        if length % 4 != 0 {
            return Err(Error::vrm(format!(
                "GLB length {length} is not a multiple of 4 (chunks must be 4-byte aligned)"
            )));
        }

        let mut json = None;
        let mut bin = 0..0;
        let mut offset = HEADER_LEN;
        let mut index = 0usize;
        while offset < length {
            let what = if index == 0 {
                "JSON chunk".to_string()
            } else {
                format!("chunk {index}")
            };
            let (Some(chunk_len), Some(kind)) =
                (read_u32(bytes, offset), read_u32(bytes, offset + 4))
            else {
                return Err(Error::vrm(format!(
                    "truncated: {what} header at byte {offset} needs {CHUNK_HEADER_LEN} bytes, \
                     the file ends at byte {length}"
                )));
            };
            let chunk_len = chunk_len as usize;
            let start = offset + CHUNK_HEADER_LEN;
            let end = start
                .checked_add(chunk_len)
                .filter(|&e| e <= length)
                .ok_or_else(|| {
                    Error::vrm(format!(
                        "{what} of {chunk_len} bytes at byte {start} extends past the end of \
                         the file ({length} bytes)"
                    ))
                })?;
            if chunk_len % 4 != 0 {
                return Err(Error::vrm(format!(
                    "{what} length {chunk_len} is not a multiple of 4 (chunks must be 4-byte \
                     aligned)"
                )));
            }
            let data = bytes.get(start..end).ok_or_else(|| {
                Error::vrm(format!("{what} at bytes {start}..{end} is out of bounds"))
            })?;
            match (index, kind) {
                (0, CHUNK_JSON) if chunk_len > MAX_JSON_BYTES => {
                    return Err(Error::vrm(format!(
                    "JSON chunk of {chunk_len} bytes, more than the {MAX_JSON_BYTES} handrig reads"
                )))
                }
                (0, CHUNK_JSON) => json = Some(data),
                (0, other) => {
                    return Err(Error::vrm(format!(
                        "the first chunk must be the JSON chunk (type \"JSON\"), found type {}",
                        show_tag(other)
                    )))
                }
                (_, CHUNK_JSON) => {
                    return Err(Error::vrm(format!("chunk {index}: a second JSON chunk")));
                }
                (1, CHUNK_BIN) => bin = start..end,
                (_, CHUNK_BIN) => {
                    return Err(Error::vrm(format!(
                        "chunk {index}: a BIN chunk must directly follow the JSON chunk"
                    )));
                }
                // The GLB spec says readers skip chunk types they do not know.
                _ => {}
            }
            offset = end;
            index += 1;
        }
        let json = json.ok_or_else(|| {
            Error::vrm(format!(
                "JSON chunk missing: the file ends after the {HEADER_LEN}-byte header"
            ))
        })?;
        Ok(Glb { json, bin })
    }
}
