//! A rendered picture: RGBA8 (sRGB) pixels, rows from the top; PNG in and out; comparison.

use crate::RenderError;
use std::path::Path;

/// An RGBA8 picture, rows from the top, no padding.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    width: u32,
    height: u32,
    rgba: Vec<u8>,
}

/// How two frames differ.
#[derive(Clone, Debug)]
pub struct Difference {
    /// The largest difference of one channel of one pixel (0-255).
    pub max: u8,
    /// Pixels with some channel differing by more than the tolerance.
    pub pixels_over: usize,
    /// The difference picture: per-channel absolute differences, scaled up to be seen.
    pub image: Frame,
}

impl Frame {
    /// A frame from its pixels (`rgba.len()` must be `4 * width * height`).
    pub fn new(width: u32, height: u32, rgba: Vec<u8>) -> Frame {
        debug_assert_eq!(rgba.len(), 4 * width as usize * height as usize);
        Frame {
            width,
            height,
            rgba,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixels, RGBA8, rows from the top.
    pub fn rgba(&self) -> &[u8] {
        &self.rgba
    }

    /// The pixel at column `x`, row `y` (from the top), or `None` outside.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        self.rgba.get(i..i + 4).and_then(|p| p.try_into().ok())
    }

    /// Writes the frame as a PNG (creating the folder), whole or not at all.
    pub fn save_png(&self, path: &Path) -> Result<(), RenderError> {
        let io = |source| RenderError::Io {
            path: path.display().to_string(),
            source,
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        let mut bytes = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut bytes, self.width, self.height);
            encoder.set_color(png::ColorType::Rgba);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
            let png_error = |e: png::EncodingError| RenderError::Png {
                path: path.display().to_string(),
                detail: e.to_string(),
            };
            let mut writer = encoder.write_header().map_err(png_error)?;
            writer.write_image_data(&self.rgba).map_err(png_error)?;
        }
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".partial");
        std::fs::write(&tmp, &bytes).map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    }

    /// Reads an 8-bit RGB or RGBA PNG.
    pub fn load_png(path: &Path) -> Result<Frame, RenderError> {
        let bad = |detail: String| RenderError::Png {
            path: path.display().to_string(),
            detail,
        };
        let file = std::fs::File::open(path).map_err(|source| RenderError::Io {
            path: path.display().to_string(),
            source,
        })?;
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .map_err(|e| bad(e.to_string()))?;
        let mut buf = vec![
            0;
            reader
                .output_buffer_size()
                .ok_or_else(|| bad("image too large".into()))?
        ];
        let info = reader
            .next_frame(&mut buf)
            .map_err(|e| bad(e.to_string()))?;
        let data = &buf[..info.buffer_size()];
        let rgba = match (info.color_type, info.bit_depth) {
            (png::ColorType::Rgba, png::BitDepth::Eight) => data.to_vec(),
            (png::ColorType::Rgb, png::BitDepth::Eight) => data
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect(),
            (c, d) => {
                return Err(bad(format!(
                    "{c:?} at {d:?} bits: only 8-bit RGB or RGBA is read"
                )));
            }
        };
        Ok(Frame::new(info.width, info.height, rgba))
    }

    /// How `self` differs from `other` (same size), counting pixels with a channel more than
    /// `tolerance` apart. `None` if the sizes differ.
    pub fn difference(&self, other: &Frame, tolerance: u8) -> Option<Difference> {
        if (self.width, self.height) != (other.width, other.height) {
            return None;
        }
        let mut max = 0;
        let mut pixels_over = 0;
        let mut image = Vec::with_capacity(self.rgba.len());
        for (a, b) in self.rgba.chunks_exact(4).zip(other.rgba.chunks_exact(4)) {
            let d: Vec<u8> = a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).collect();
            let worst = d.iter().copied().max().unwrap_or(0);
            max = max.max(worst);
            if worst > tolerance {
                pixels_over += 1;
            }
            image.extend(d[..3].iter().map(|&c| c.saturating_mul(16)));
            image.push(255);
        }
        Some(Difference {
            max,
            pixels_over,
            image: Frame::new(self.width, self.height, image),
        })
    }
}
