//! Drawing clipped 2D segments: the last stage of the pipeline.
//!
//! Input is a [`LineScene`]: coloured batches of [`Segment2`] in **pixel coordinates** (origin
//! at the top-left corner of the image, x right, y down; pixel (i, j) covers [i, i+1)×[j, j+1),
//! its centre is (i + ½, j + ½)). Backends:
//!
//! * [`cpu`]: Bresenham into an RGBA8 buffer; bit-exact and deterministic (golden images).
//! * `gpu` (with the `gpu` feature, on by default): wgpu LineList pipeline into an offscreen
//!   texture, read back (any adapter, Mesa lavapipe included).
//! * [`svg`]: the exact segments as vector lines.
//!
//! [`Rasterizer`] picks a backend at run time (the CPU one in a build without the `gpu`
//! feature). Writing pictures to files is [`crate::output`]'s job.

pub mod cpu;
pub mod gif;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod rasterizer;
pub mod svg;

pub use rasterizer::{Backend, OutputFormat, Rasterizer, RenderError, UnknownFormat};

pub use wireflight_geometry::lines::{LineBatch, LineScene, Rgba, Segment2};

/// Why PNG bytes could not be read as an [`Image`] ([`Image::decode_png`]).
#[derive(Debug, thiserror::Error)]
pub enum DecodePngError {
    /// The PNG decoder failed.
    #[error(transparent)]
    Png(#[from] png::DecodingError),
    /// A PNG that is not 8-bit RGB or RGBA.
    #[error("unsupported PNG layout {color:?} {depth:?}")]
    Layout {
        /// Its colour type.
        color: png::ColorType,
        /// Its bit depth.
        depth: png::BitDepth,
    },
}

/// An RGBA8 image, rows top to bottom, tightly packed (`width * 4` bytes per row).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

impl Image {
    /// An image filled with one colour.
    pub fn filled(width: u32, height: u32, color: Rgba) -> Self {
        let n = width as usize * height as usize;
        let mut pixels = Vec::with_capacity(n * 4);
        for _ in 0..n {
            pixels.extend_from_slice(&color);
        }
        Self {
            width,
            height,
            pixels,
        }
    }

    /// The pixel at (x, y).
    ///
    /// # Panics
    /// If (x, y) is outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Rgba {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside image"
        );
        let i = (y as usize * self.width as usize + x as usize) * 4;
        // A slice of exactly 4 bytes (inside the image, asserted above) converts to [u8; 4].
        self.pixels[i..i + 4].try_into().unwrap()
    }

    /// PNG bytes of the image (8-bit RGBA).
    ///
    /// # Errors
    /// Only if the encoder fails (it does not for valid images).
    pub fn encode_png(&self) -> Result<Vec<u8>, png::EncodingError> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, self.width, self.height);
            enc.set_color(png::ColorType::Rgba);
            enc.set_depth(png::BitDepth::Eight);
            let mut writer = enc.write_header()?;
            writer.write_image_data(&self.pixels)?;
        }
        Ok(out)
    }

    /// Decode an 8-bit RGBA or RGB PNG (golden images, tests).
    ///
    /// # Errors
    /// Decoding errors, or a PNG that is not 8-bit RGB(A).
    pub fn decode_png(bytes: &[u8]) -> Result<Self, DecodePngError> {
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info()?;
        let mut buf = vec![0; reader.output_buffer_size().unwrap_or(0)];
        let info = reader.next_frame(&mut buf)?;
        buf.truncate(info.buffer_size());
        let pixels = match (info.color_type, info.bit_depth) {
            (png::ColorType::Rgba, png::BitDepth::Eight) => buf,
            (png::ColorType::Rgb, png::BitDepth::Eight) => buf
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect(),
            (color, depth) => return Err(DecodePngError::Layout { color, depth }),
        };
        Ok(Self {
            width: info.width,
            height: info.height,
            pixels,
        })
    }
}
