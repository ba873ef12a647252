//! Animated GIF: frames of [`Image`]s encoded in memory, each with its own palette of the
//! colours it uses (wireframes use a handful, so nothing is lost); a frame with more than 256
//! colours is quantised (NeuQuant). Loops forever.

use std::collections::HashMap;

use super::Image;

/// Why an animation could not be made or a frame added.
#[derive(Debug, thiserror::Error)]
pub enum GifError {
    /// A side of zero or over 65 535 pixels.
    #[error("a GIF is 1..=65535 pixels a side, not {width}x{height}")]
    Size {
        /// Requested width, pixels.
        width: u32,
        /// Requested height, pixels.
        height: u32,
    },
    /// A frame delay of zero.
    #[error("a GIF frame lasts at least 1/100 s")]
    ZeroDelay,
    /// A frame of another size than the animation.
    #[error(
        "frame {frame} is {width}x{height}, the animation {animation_width}x{animation_height}"
    )]
    FrameSize {
        /// Index of the frame (0-based).
        frame: usize,
        /// The frame's width, pixels.
        width: u32,
        /// The frame's height, pixels.
        height: u32,
        /// The animation's width, pixels.
        animation_width: u16,
        /// The animation's height, pixels.
        animation_height: u16,
    },
    /// The encoder failed. (Its error is in the message, not a `source`: the encoder's own
    /// message already is its source's, and a chain would print it twice.)
    #[error("{0}")]
    Encode(gif::EncodingError),
}

/// An animation being encoded.
pub struct GifAnimation {
    encoder: gif::Encoder<Vec<u8>>,
    width: u16,
    height: u16,
    delay_cs: u16,
    frames: usize,
}

impl GifAnimation {
    /// An animation of `width`×`height` frames shown `delay_cs` hundredths of a second each.
    ///
    /// # Errors
    /// A side over 65 535 pixels or zero, a zero delay.
    pub fn new(width: u32, height: u32, delay_cs: u16) -> Result<Self, GifError> {
        let side = |v: u32| u16::try_from(v).ok().filter(|&v| v > 0);
        let (Some(w), Some(h)) = (side(width), side(height)) else {
            return Err(GifError::Size { width, height });
        };
        if delay_cs == 0 {
            return Err(GifError::ZeroDelay);
        }
        let mut encoder = gif::Encoder::new(Vec::new(), w, h, &[]).map_err(GifError::Encode)?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(GifError::Encode)?;
        Ok(Self {
            encoder,
            width: w,
            height: h,
            delay_cs,
            frames: 0,
        })
    }

    /// The delay that shows `fps` frames per second as nearly as a GIF can (hundredths of a
    /// second, at least 1).
    pub fn delay_for(fps: f64) -> u16 {
        (100.0 / fps).round().clamp(1.0, u16::MAX as f64) as u16
    }

    /// Appends a frame.
    ///
    /// # Errors
    /// An image of another size; encoder errors.
    pub fn push(&mut self, image: &Image) -> Result<(), GifError> {
        if (image.width, image.height) != (self.width as u32, self.height as u32) {
            return Err(GifError::FrameSize {
                frame: self.frames,
                width: image.width,
                height: image.height,
                animation_width: self.width,
                animation_height: self.height,
            });
        }
        let mut frame = match indexed(image) {
            Some((pixels, palette)) => {
                gif::Frame::from_palette_pixels(self.width, self.height, pixels, palette, None)
            }
            None => {
                let mut rgba = image.pixels.clone();
                gif::Frame::from_rgba_speed(self.width, self.height, &mut rgba, 10)
            }
        };
        frame.delay = self.delay_cs;
        self.encoder.write_frame(&frame).map_err(GifError::Encode)?;
        self.frames += 1;
        Ok(())
    }

    /// Frames so far.
    pub fn len(&self) -> usize {
        self.frames
    }

    /// True before the first frame.
    pub fn is_empty(&self) -> bool {
        self.frames == 0
    }

    /// The GIF file's bytes.
    ///
    /// # Errors
    /// Encoder errors.
    pub fn finish(self) -> Result<Vec<u8>, GifError> {
        self.encoder.into_inner().map_err(GifError::Encode)
    }
}

/// The image as palette indices and an RGB palette, when it has at most 256 colours (alpha
/// ignored).
fn indexed(image: &Image) -> Option<(Vec<u8>, Vec<u8>)> {
    let mut index: HashMap<[u8; 3], u8> = HashMap::new();
    let mut palette = Vec::new();
    let mut pixels = Vec::with_capacity(image.pixels.len() / 4);
    // Most neighbours share a colour (the background): look the colour up only when it changes.
    let mut last: Option<([u8; 3], u8)> = None;
    for p in image.pixels.chunks_exact(4) {
        let rgb = [p[0], p[1], p[2]];
        if let Some((c, i)) = last {
            if c == rgb {
                pixels.push(i);
                continue;
            }
        }
        let i = match index.get(&rgb) {
            Some(&i) => i,
            None => {
                let i = u8::try_from(index.len()).ok()?;
                index.insert(rgb, i);
                palette.extend_from_slice(&rgb);
                i
            }
        };
        last = Some((rgb, i));
        pixels.push(i);
    }
    Some((pixels, palette))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_keep_their_colours() {
        let mut a = GifAnimation::new(4, 3, GifAnimation::delay_for(25.0)).unwrap();
        let mut img = Image::filled(4, 3, [10, 20, 30, 255]);
        a.push(&img).unwrap();
        img.pixels[4..8].copy_from_slice(&[200, 0, 0, 255]);
        a.push(&img).unwrap();
        assert_eq!(a.len(), 2);
        let err = a.push(&Image::filled(3, 3, [0, 0, 0, 255])).unwrap_err();
        assert_eq!(err.to_string(), "frame 2 is 3x3, the animation 4x3");
        let bytes = a.finish().unwrap();
        assert!(bytes.starts_with(b"GIF89a"));
        // Decode and compare.
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::RGBA);
        let mut d = opts.read_info(&bytes[..]).unwrap();
        let f1 = d.read_next_frame().unwrap().unwrap().buffer.to_vec();
        assert_eq!(&f1[..4], &[10, 20, 30, 255]);
        let f2 = d.read_next_frame().unwrap().unwrap();
        assert_eq!(f2.delay, 4);
        assert_eq!(&f2.buffer[4..8], &[200, 0, 0, 255]);
        assert_eq!(
            GifAnimation::new(0, 3, 4)
                .err()
                .map(|e| e.to_string())
                .as_deref(),
            Some("a GIF is 1..=65535 pixels a side, not 0x3")
        );
        assert_eq!(GifAnimation::delay_for(10.0), 10);
    }
}
