//! Animated GIF: frames of [`Image`]s encoded in memory, each with its own palette of the
//! colours it uses (wireframes use a handful, so nothing is lost); a frame with more than 256
//! colours is quantised (NeuQuant). Loops forever.

use std::collections::HashMap;

use super::Image;

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
    pub fn new(width: u32, height: u32, delay_cs: u16) -> Result<Self, String> {
        let side = |v: u32| u16::try_from(v).ok().filter(|&v| v > 0);
        let (Some(w), Some(h)) = (side(width), side(height)) else {
            return Err(format!(
                "a GIF is 1..=65535 pixels a side, not {width}x{height}"
            ));
        };
        if delay_cs == 0 {
            return Err("a GIF frame lasts at least 1/100 s".into());
        }
        let mut encoder = gif::Encoder::new(Vec::new(), w, h, &[]).map_err(|e| e.to_string())?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| e.to_string())?;
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
    pub fn push(&mut self, image: &Image) -> Result<(), String> {
        if (image.width, image.height) != (self.width as u32, self.height as u32) {
            return Err(format!(
                "frame {} is {}x{}, the animation {}x{}",
                self.frames, image.width, image.height, self.width, self.height
            ));
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
        self.encoder
            .write_frame(&frame)
            .map_err(|e| e.to_string())?;
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
    pub fn finish(self) -> Result<Vec<u8>, String> {
        self.encoder.into_inner().map_err(|e| e.to_string())
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
        assert!(a.push(&Image::filled(3, 3, [0, 0, 0, 255])).is_err());
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
        assert!(GifAnimation::new(0, 3, 4).is_err());
        assert_eq!(GifAnimation::delay_for(10.0), 10);
    }
}
