//! Rendered images and their output formats (8-bit PNG of the linear values tagged
//! `gAMA` 1.0 or sRGB-encoded and tagged `sRGB`, linear float PFM), written atomically:
//! to a temporary file beside the target, then renamed.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// A linear RGB image, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` linear RGB values.
    pub pixels: Vec<[f32; 3]>,
}

impl Image {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![[0.0; 3]; width as usize * height as usize],
        }
    }

    /// The pixel at column `x`, row `y` (from the top).
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// 8-bit RGB bytes: each channel clamped to [0, 1], scaled by 255 and rounded (the
    /// linear values, with no transfer curve).
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8))
            .collect()
    }

    /// 8-bit sRGB bytes: each channel clamped to [0, 1], encoded with the sRGB transfer
    /// function ([`srgb_encode`]), scaled by 255 and rounded.
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.map(|c| (srgb_encode(c.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8))
            .collect()
    }

    /// Writes the image, choosing the format by extension: `.png` (8-bit) or `.pfm`
    /// (linear 32-bit float). The file appears complete or not at all.
    ///
    /// # Errors
    /// An unknown extension, or any I/O error (the temporary file is removed).
    pub fn save(&self, path: &Path) -> io::Result<()> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => write_atomic(path, |w| self.write_png(w)),
            Some("pfm") => write_atomic(path, |w| self.write_pfm(w)),
            _ => Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "output must end in .png or .pfm",
            )),
        }
    }

    /// Encodes as an 8-bit RGB PNG of the linear values ([`Image::to_rgb8`]), tagged as
    /// such: a `gAMA` chunk of 1.0.
    pub fn write_png<W: Write>(&self, w: W) -> io::Result<()> {
        self.write_png_as(w, PngEncoding::Linear)
    }

    /// Encodes as an 8-bit RGB PNG with `encoding`, tagged with it.
    pub fn write_png_as<W: Write>(&self, w: W, encoding: PngEncoding) -> io::Result<()> {
        let mut enc = png::Encoder::new(w, self.width, self.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let bytes = match encoding {
            PngEncoding::Linear => {
                enc.set_source_gamma(png::ScaledFloat::new(1.0));
                self.to_rgb8()
            }
            PngEncoding::Srgb => {
                enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
                // The gAMA value the PNG specification pairs with sRGB, for decoders
                // that read no sRGB chunk.
                enc.set_source_gamma(png::ScaledFloat::from_scaled(45455));
                self.to_srgb8()
            }
        };
        let mut writer = enc.write_header().map_err(io::Error::other)?;
        writer.write_image_data(&bytes).map_err(io::Error::other)?;
        writer.finish().map_err(io::Error::other)
    }

    /// Encodes as a little-endian colour PFM (rows bottom to top, as the format says).
    pub fn write_pfm<W: Write>(&self, mut w: W) -> io::Result<()> {
        write!(w, "PF\n{} {}\n-1.0\n", self.width, self.height)?;
        for y in (0..self.height).rev() {
            for x in 0..self.width {
                for c in self.get(x, y) {
                    w.write_all(&c.to_le_bytes())?;
                }
            }
        }
        Ok(())
    }

    /// Reads an 8-bit RGB or RGBA PNG (for comparisons against reference images).
    ///
    /// # Errors
    /// I/O or decoding errors, or an unsupported PNG colour type.
    pub fn read_png(path: &Path) -> io::Result<Self> {
        let dec = png::Decoder::new(io::BufReader::new(fs::File::open(path)?));
        let mut reader = dec.read_info().map_err(io::Error::other)?;
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).map_err(io::Error::other)?;
        let channels = match (info.color_type, info.bit_depth) {
            (png::ColorType::Rgb, png::BitDepth::Eight) => 3,
            (png::ColorType::Rgba, png::BitDepth::Eight) => 4,
            other => {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!("unsupported PNG format {other:?}"),
                ))
            }
        };
        let pixels = buf[..info.buffer_size()]
            .chunks_exact(channels)
            .map(|p| [p[0], p[1], p[2]].map(|c| c as f32 / 255.0))
            .collect();
        Ok(Self {
            width: info.width,
            height: info.height,
            pixels,
        })
    }
}

/// How the 8-bit values of a PNG encode the image's linear values, and so how the file
/// is tagged.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PngEncoding {
    /// The linear values themselves, clamped and scaled (as classic NFF renderers write
    /// them), tagged `gAMA` 1.0.
    #[default]
    Linear,
    /// sRGB-encoded values, tagged with an `sRGB` chunk (and the matching `gAMA`).
    Srgb,
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1], computed in
/// `f64`: $12.92 c$ up to $0.0031308$, else $1.055 c^{1/2.4} - 0.055$.
pub fn srgb_encode(c: f32) -> f32 {
    let c = f64::from(c);
    let v = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    v as f32
}

/// Runs `write` into a temporary file next to `path`, syncs it, and renames it over
/// `path`; on any error the temporary file is removed and `path` is untouched.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<fs::File>) -> io::Result<()>,
) -> io::Result<()> {
    let tmp = temp_path(path);
    let result = (|| {
        let mut w = BufWriter::new(fs::File::create(&tmp)?);
        write(&mut w)?;
        let f = w.into_inner().map_err(|e| e.into_error())?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}
