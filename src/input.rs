//! Reading a scene's text from a file or standard input without reading forever: a scene is a
//! JSON object, so reading stops at the first byte that cannot be part of one (a device such
//! as `/dev/zero`, a binary file), and at [`MAX_SCENE_BYTES`].

use std::io::{self, Read};

/// The largest scene text read, in bytes (16 GiB: about a hundred million objects).
pub const MAX_SCENE_BYTES: u64 = 16 << 30;

/// The UTF-8 byte-order mark, skipped before a scene.
const BOM: [u8; 3] = [0xef, 0xbb, 0xbf];

/// Why a scene's text could not be read.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The reader failed.
    #[error("cannot read: {0}")]
    Read(#[from] io::Error),
    /// A byte no scene can hold at that place.
    #[error("{why}: byte 0x{byte:02x} at offset {offset}")]
    NotAScene {
        /// The byte.
        byte: u8,
        /// Its offset from the start.
        offset: u64,
        /// Why it cannot be there.
        why: &'static str,
    },
    /// The text runs past [`MAX_SCENE_BYTES`].
    #[error("longer than {MAX_SCENE_BYTES} bytes, the most a scene may hold")]
    TooLong,
    /// The bytes are not UTF-8.
    #[error("not UTF-8 text: {0}")]
    NotText(#[from] std::string::FromUtf8Error),
}

/// Reads the whole text of a scene from `reader`, checking each chunk as it comes: the first
/// byte that is not white space must open a JSON object (`{`), and no control byte other than
/// white space may appear (JSON allows none outside strings, and none inside them unescaped).
pub fn read_scene_text(mut reader: impl Read) -> Result<String, InputError> {
    let mut text: Vec<u8> = Vec::new();
    let mut chunk = vec![0u8; 1 << 16];
    let mut opened = false;
    loop {
        let got = match reader.read(&mut chunk) {
            Ok(0) => break,
            Ok(got) => got,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e.into()),
        };
        let start = text.len() as u64;
        // Once the scene has opened, only a control byte stops it: looked for in one pass
        // (a scene of 32,000 spheres is 10 MB).
        let control = |b: u8| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r');
        let checked = if opened {
            // A pass without a branch a byte, then the byte itself where there is one.
            let any = chunk[..got].iter().fold(false, |any, &b| any | control(b));
            if any {
                chunk[..got].iter().position(|&b| control(b)).unwrap_or(got)
            } else {
                got
            }
        } else {
            0
        };
        for (k, &byte) in chunk[checked..got].iter().enumerate() {
            let offset = start + (checked + k) as u64;
            let space = matches!(byte, b' ' | b'\t' | b'\n' | b'\r');
            // A UTF-8 byte-order mark may come first.
            let mark = offset < 3 && byte == BOM[offset as usize];
            if !opened && !space && !mark {
                if byte != b'{' {
                    let json = matches!(byte, b'[' | b'"' | b'-' | b'0'..=b'9' | b't' | b'f');
                    return Err(InputError::NotAScene {
                        byte,
                        offset,
                        why: if json {
                            "a scene must be a JSON object, and this cannot begin a scene"
                        } else {
                            "not valid JSON, and this cannot begin a scene"
                        },
                    });
                }
                opened = true;
            }
            if control(byte) {
                return Err(InputError::NotAScene {
                    byte,
                    offset,
                    why: "not valid JSON: a control byte, which a scene cannot hold",
                });
            }
        }
        if start + got as u64 > MAX_SCENE_BYTES {
            return Err(InputError::TooLong);
        }
        text.extend_from_slice(&chunk[..got]);
    }
    Ok(String::from_utf8(text)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_reads_whole_and_other_bytes_stop_at_once() {
        let scene = " \n{\"world\": \"free\"}\n";
        assert_eq!(read_scene_text(scene.as_bytes()).unwrap(), scene);
        let marked = "\u{feff}{}";
        assert_eq!(read_scene_text(marked.as_bytes()).unwrap(), marked);
        // An endless stream of zero bytes stops at the first.
        let zeros = io::repeat(0).take(1 << 40);
        match read_scene_text(zeros) {
            Err(InputError::NotAScene {
                byte: 0, offset: 0, ..
            }) => {}
            other => panic!("{other:?}"),
        }
        // A scene that turns into zeros stops at the first zero.
        let tail = b"{\"world\"".chain(io::repeat(0).take(1 << 40));
        match read_scene_text(tail) {
            Err(InputError::NotAScene {
                byte: 0, offset: 8, ..
            }) => {}
            other => panic!("{other:?}"),
        }
        match read_scene_text("  [1, 2]".as_bytes()) {
            Err(InputError::NotAScene {
                byte: b'[',
                offset: 2,
                ..
            }) => {}
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            read_scene_text(&b"{\"a\": \"\xff\"}"[..]),
            Err(InputError::NotText(_))
        ));
    }
}
