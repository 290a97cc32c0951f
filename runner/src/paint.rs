//! Painted maps read from PNG files: `--density-map`, `--height-map`,
//! `--colour-map` and `--type-map` lay an image over the world's square (its top row at −z):
//! `shared::paint` says what each means. Every way a file can be unusable is an error
//! naming the map and the file; files are opened through [`crate::files`].

use anyhow::{Context as _, Result, bail};
use image::codecs::png::PngDecoder;
use image::{ColorType, ImageDecoder};
use std::path::Path;

/// Largest side of a map (pixels): 4096 × 4096 is 64 MiB of texels on the device.
pub const MAX_SIDE: u32 = 4096;

/// Most bytes a map's file may have: the largest map's texels, uncompressed, and some.
pub const MAX_FILE_BYTES: u64 = (MAX_SIDE as u64 * MAX_SIDE as u64 * 4) * 2;

/// One map: which (`shared::world::paint::DENSITY`, ...), its size and its RGBA texels.
pub type Map = (usize, u32, u32, Vec<[u8; 4]>);

/// The maps the command line names, as `shared::paint` words (empty for none).
pub fn load_all(
    density: Option<&Path>,
    height: Option<&Path>,
    colour: Option<&Path>,
    kind: Option<&Path>,
) -> Result<Vec<u32>> {
    use shared::world::paint::{COLOUR, DENSITY, HEIGHT, TYPE};
    let mut maps = Vec::new();
    let named = [
        (DENSITY, density),
        (HEIGHT, height),
        (COLOUR, colour),
        (TYPE, kind),
    ];
    for (which, path) in named {
        if let Some(path) = path {
            maps.push(load(path, which)?);
        }
    }
    if maps.is_empty() {
        return Ok(Vec::new());
    }
    let refs: Vec<_> = maps
        .iter()
        .map(|(which, w, h, texels)| (*which, *w, *h, texels.as_slice()))
        .collect();
    Ok(shared::world::paint::words(&refs))
}

/// Map `which` in `path`: an 8-bit PNG (grey, grey and alpha, RGB or RGBA), at most
/// [`MAX_SIDE`] pixels a side; the density, height and type maps are read as grey
/// (their luminance), the colour map as it is.
pub fn load(path: &Path, which: usize) -> Result<Map> {
    let name = ["density", "height", "colour", "type"][which.min(3)];
    load_named(path, which).map_err(|e| e.context(format!("{name} map")))
}

fn load_named(path: &Path, which: usize) -> Result<Map> {
    use std::io::{Read, Seek};
    let shown = path.display();
    let (file, size) = crate::files::open(path).with_context(|| shown.to_string())?;
    if size > MAX_FILE_BYTES {
        bail!("{shown}: {size} bytes, more than the {MAX_FILE_BYTES} a map may have");
    }
    let mut file = file;
    // Every PNG starts with these eight bytes (PNG specification, 5.2); read first, so
    // that no other file (a device, a pipe) is read further.
    let mut signature = [0u8; 8];
    let read = file
        .read(&mut signature)
        .with_context(|| format!("{shown}: cannot read it"))?;
    if read < signature.len() || signature != [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'] {
        bail!("{shown}: not a PNG image");
    }
    file.rewind()
        .with_context(|| format!("{shown}: cannot read it"))?;
    let unreadable = || format!("{shown}: not a readable PNG");
    let decoder = PngDecoder::new(std::io::BufReader::new(file)).with_context(unreadable)?;
    let (width, height) = decoder.dimensions();
    if width == 0 || height == 0 {
        bail!("{shown}: the image has no pixels ({width}x{height})");
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        bail!("{shown}: {width}x{height} pixels, more than {MAX_SIDE} a side");
    }
    let image = image::DynamicImage::from_decoder(decoder).with_context(unreadable)?;
    let color = image.color();
    if !matches!(
        color,
        ColorType::L8 | ColorType::La8 | ColorType::Rgb8 | ColorType::Rgba8
    ) {
        bail!("{shown}: {color:?} pixels; save it with 8 bits a channel");
    }
    let texels = if which == shared::world::paint::COLOUR {
        image.to_rgba8().pixels().map(|p| p.0).collect()
    } else {
        shared::world::paint::grey(image.to_luma8().as_raw())
    };
    Ok((which, width, height, texels))
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::ImageFormat;

    fn temp(name: &str) -> std::path::PathBuf {
        std::env::temp_dir().join(format!("grass-paint-{}-{name}", std::process::id()))
    }

    /// PNG's CRC-32 (ISO 3309), bit by bit: the test's edited header needs one.
    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &b in bytes {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 != 0 {
                    (crc >> 1) ^ 0xedb8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }

    #[test]
    fn a_grey_png_becomes_its_words() {
        let path = temp("ok.png");
        image::GrayImage::from_raw(3, 1, vec![0, 128, 255])
            .unwrap()
            .save(&path)
            .unwrap();
        let (which, w, h, texels) = load(&path, shared::world::paint::DENSITY).unwrap();
        assert_eq!((which, w, h), (shared::world::paint::DENSITY, 3, 1));
        assert_eq!(
            texels,
            vec![[0, 0, 0, 255], [128, 128, 128, 255], [255, 255, 255, 255]]
        );
        let words = load_all(Some(&path), None, Some(&path), None).unwrap();
        assert_eq!(words[shared::world::paint::HEIGHT], 0, "no height map");
        assert!(
            words[shared::world::paint::DENSITY] > 0 && words[shared::world::paint::COLOUR] > 0
        );
        std::fs::remove_file(path).ok();
    }

    #[test]
    fn each_bad_file_is_named_with_what_is_wrong() {
        let missing = temp("missing.png");
        let error = format!("{:#}", load(&missing, 0).unwrap_err());
        assert!(
            error.contains("file not found") && error.contains("missing.png"),
            "{error}"
        );
        // A named pipe is refused at once, never waited on for a writer.
        let pipe = temp("pipe.png");
        let _ = std::fs::remove_file(&pipe);
        let made = std::process::Command::new("mkfifo").arg(&pipe).status();
        assert!(made.expect("run mkfifo").success());
        let error = format!("{:#}", load(&pipe, 0).unwrap_err());
        assert!(error.contains("named pipe"), "{error}");
        let text = temp("text.png");
        std::fs::write(&text, "not an image").unwrap();
        let error = format!("{:#}", load(&text, 0).unwrap_err());
        assert!(
            error.contains("not a PNG") && error.contains("text.png"),
            "{error}"
        );
        let jpeg = temp("photo.jpg");
        image::RgbImage::new(4, 4).save(&jpeg).unwrap();
        assert!(format!("{:#}", load(&jpeg, 0).unwrap_err()).contains("not a PNG"));
        let deep = temp("deep.png");
        image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::new(2, 2)
            .save(&deep)
            .unwrap();
        let error = format!("{:#}", load(&deep, 1).unwrap_err());
        assert!(
            error.contains("8 bits") && error.contains("deep.png"),
            "{error}"
        );
        let cut = temp("cut.png");
        let mut bytes = Vec::new();
        image::GrayImage::new(64, 64)
            .write_to(&mut std::io::Cursor::new(&mut bytes), ImageFormat::Png)
            .unwrap();
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        assert!(format!("{:#}", load(&cut, 2).unwrap_err()).contains("cut.png"));
        // A header claiming 100000 x 1 pixels (no need for the pixels: it is refused
        // before they are read).
        let huge = temp("huge.png");
        let mut bytes = Vec::new();
        image::GrayImage::new(1, 1)
            .write_to(&mut std::io::Cursor::new(&mut bytes), ImageFormat::Png)
            .unwrap();
        bytes[16..20].copy_from_slice(&100_000u32.to_be_bytes());
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        std::fs::write(&huge, &bytes).unwrap();
        let error = format!("{:#}", load(&huge, 0).unwrap_err());
        assert!(
            error.contains("more than 4096") && error.contains("huge.png"),
            "{error}"
        );
        for p in [pipe, text, jpeg, deep, cut, huge] {
            std::fs::remove_file(p).ok();
        }
    }
}
