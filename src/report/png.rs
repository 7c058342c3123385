//! The smallest PNG writer that browsers read: 8-bit RGB, every scanline unfiltered, the
//! zlib stream made of stored (uncompressed) deflate blocks, and a base64 data URI of it,
//! so the verdict page can embed images without a network asset or a dependency.
//!
//! Formats: PNG (ISO/IEC 15948, W3C PNG 2nd ed.: signature, IHDR, IDAT, IEND chunks each
//! with a CRC-32 of type and data), zlib (RFC 1950: CMF/FLG header, Adler-32 trailer),
//! deflate stored blocks (RFC 1951 §3.2.4: BFINAL/BTYPE byte, LEN, NLEN), base64
//! (RFC 4648 §4).

/// CRC-32 (polynomial 0xEDB88320, reflected) of `bytes`, as PNG's chunks carry it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 == 1 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// Adler-32 of `bytes` (zlib's trailer).
fn adler32(bytes: &[u8]) -> u32 {
    let (mut a, mut b) = (1u32, 0u32);
    for &x in bytes {
        a = (a + x as u32) % 65521;
        b = (b + a) % 65521;
    }
    (b << 16) | a
}

/// `data` as a zlib stream of stored deflate blocks (at most 65 535 bytes each).
fn zlib_stored(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let mut blocks = data.chunks(65_535).peekable();
    if blocks.peek().is_none() {
        out.extend_from_slice(&[1, 0, 0, 0xFF, 0xFF]);
    }
    while let Some(block) = blocks.next() {
        out.push(u8::from(blocks.peek().is_none()));
        let len = block.len() as u16;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(block);
    }
    out.extend_from_slice(&adler32(data).to_be_bytes());
    out
}

fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// A `w` × `h` 8-bit RGB PNG of `rgb` (row 0 at the top, 3 bytes per pixel).
pub fn encode_rgb(w: usize, h: usize, rgb: &[u8]) -> Vec<u8> {
    assert_eq!(rgb.len(), w * h * 3, "rgb must hold w × h pixels");
    let mut raw = Vec::with_capacity(h * (1 + 3 * w));
    for row in rgb.chunks(3 * w.max(1)).take(h) {
        raw.push(0); // filter type 0: none
        raw.extend_from_slice(row);
    }
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&(w as u32).to_be_bytes());
    ihdr.extend_from_slice(&(h as u32).to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]); // 8 bits, RGB, deflate, no filter set, no interlace
    chunk(&mut png, b"IHDR", &ihdr);
    chunk(&mut png, b"IDAT", &zlib_stored(&raw));
    chunk(&mut png, b"IEND", &[]);
    png
}

/// Standard base64 (with padding) of `bytes`.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for g in bytes.chunks(3) {
        let n = (g[0] as u32) << 16
            | (*g.get(1).unwrap_or(&0) as u32) << 8
            | *g.get(2).unwrap_or(&0) as u32;
        for (i, shift) in [18, 12, 6, 0].into_iter().enumerate() {
            s.push(if i <= g.len() {
                ALPHABET[(n >> shift) as usize & 63] as char
            } else {
                '='
            });
        }
    }
    s
}

/// The PNG as a `data:` URI for an `<img src>`.
pub fn data_uri(png: &[u8]) -> String {
    format!("data:image/png;base64,{}", base64(png))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksums_match_their_standard_check_values() {
        // The check values of the CRC catalogue and of RFC 1950's Adler-32 on "123456789".
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(adler32(b"123456789"), 0x091E_01DE);
        assert_eq!(crc32(b"IEND"), 0xAE42_6082);
    }

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }

    #[test]
    fn a_png_is_laid_out_as_the_standard_says() {
        let (w, h) = (300, 250); // 225 000 raw bytes: four stored blocks
        let rgb: Vec<u8> = (0..w * h * 3).map(|i| (i % 251) as u8).collect();
        let png = encode_rgb(w, h, &rgb);
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        assert_eq!(&png[12..16], b"IHDR");
        assert_eq!(
            u32::from_be_bytes(png[16..20].try_into().unwrap()),
            w as u32
        );
        assert_eq!(&png[png.len() - 12..], b"\0\0\0\0IEND\xAE\x42\x60\x82");
        // Undo the stored blocks: the scanlines come back, each behind filter byte 0.
        let len = u32::from_be_bytes(png[33..37].try_into().unwrap()) as usize;
        let z = &png[41..41 + len];
        let (mut at, mut raw) = (2, Vec::new());
        loop {
            let last = z[at] == 1;
            let n = u16::from_le_bytes([z[at + 1], z[at + 2]]) as usize;
            assert_eq!(!(n as u16), u16::from_le_bytes([z[at + 3], z[at + 4]]));
            raw.extend_from_slice(&z[at + 5..at + 5 + n]);
            at += 5 + n;
            if last {
                break;
            }
        }
        assert_eq!(raw.len(), h * (1 + 3 * w));
        assert!(raw.chunks(1 + 3 * w).all(|r| r[0] == 0));
        assert_eq!(&raw[1..1 + 3 * w], &rgb[..3 * w]);
        assert_eq!(z[at..].to_vec(), adler32(&raw).to_be_bytes().to_vec());
        let crc = crc32(&png[37..41 + len]);
        assert_eq!(png[41 + len..45 + len], crc.to_be_bytes());
    }
}
