//! The wgpu backend against the CPU one.
//!
//! GPUs step lines by their own rules (diamond-exit, tie-breaking, the last pixel left out), so
//! the images are not byte-equal; they must agree to within one pixel: at least 97 % of the lit
//! (non-background) pixels of each image lie within one pixel (Chebyshev distance) of a lit
//! pixel of the other, and every lit pixel has one of the scene's line colours, byte for byte.
//!
//! Without an adapter the tests print why and pass, unless `WIREFLIGHT_REQUIRE_GPU=1` (CI sets
//! it after installing Mesa lavapipe), when they fail. The adapter's name is always printed
//! (`cargo test --test it gpu_backend:: -- --nocapture`).

use std::sync::{Mutex, MutexGuard, OnceLock};

use glam::Vec2;
use wireflight::draw::render::gpu::GpuRenderer;
use wireflight::draw::render::{cpu, Image, LineBatch, LineScene, Rgba, Segment2};
use wireflight::draw::scene::palette;
use wireflight::draw::scene::{frame, ViewSpec};
use wireflight::geometry::camera::CameraPreset;
use wireflight::geometry::euler::EulerZyx;
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::Viewport;

use crate::support::cli::wireflight;

/// Least fraction of lit pixels with a lit pixel of the other image within one pixel.
const MIN_AGREEMENT: f64 = 0.97;

fn gpu_required() -> bool {
    std::env::var("WIREFLIGHT_REQUIRE_GPU").as_deref() == Ok("1")
}

/// One renderer for the whole test binary (tests take turns), so they also exercise reusing
/// it across frames and sizes. `None`, after saying why, when there is no adapter and none is
/// required.
fn gpu() -> Option<MutexGuard<'static, GpuRenderer>> {
    static GPU: OnceLock<Result<Mutex<GpuRenderer>, String>> = OnceLock::new();
    let gpu = GPU.get_or_init(|| {
        GpuRenderer::new()
            .map(Mutex::new)
            .map_err(|e| e.to_string())
    });
    match gpu {
        Ok(renderer) => {
            let renderer = renderer.lock().unwrap_or_else(|p| p.into_inner());
            let a = renderer.adapter();
            eprintln!(
                "GPU adapter: {a} [{}; {}]",
                a.device_type,
                if a.driver.is_empty() {
                    "driver not reported"
                } else {
                    &a.driver
                }
            );
            Some(renderer)
        }
        Err(e) if gpu_required() => panic!("WIREFLIGHT_REQUIRE_GPU=1 but {e}"),
        Err(e) => {
            eprintln!("skipping the GPU test: {e} (set WIREFLIGHT_REQUIRE_GPU=1 to fail instead)");
            None
        }
    }
}

/// Lit pixels of an image: those that differ from the background.
fn lit_mask(image: &Image, background: Rgba) -> Vec<bool> {
    image
        .pixels
        .chunks_exact(4)
        .map(|p| p != background)
        .collect()
}

/// Fraction of the lit pixels of `a` that have a lit pixel of `b` in their 3×3 neighbourhood,
/// and how many lit pixels `a` has.
fn agreement(a: &[bool], b: &[bool], width: u32, height: u32) -> (f64, usize) {
    let (w, h) = (width as i64, height as i64);
    let mut lit = 0usize;
    let mut near = 0usize;
    for y in 0..h {
        for x in 0..w {
            if !a[(y * w + x) as usize] {
                continue;
            }
            lit += 1;
            let hit = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    let (u, v) = (x + dx, y + dy);
                    (0..w).contains(&u) && (0..h).contains(&v) && b[(v * w + u) as usize]
                })
            });
            near += usize::from(hit);
        }
    }
    let fraction = if lit == 0 {
        1.0
    } else {
        near as f64 / lit as f64
    };
    (fraction, lit)
}

/// Render `scene` on both backends and hold them to the agreement rule. Returns the GPU image.
fn assert_backends_agree(name: &str, renderer: &mut GpuRenderer, scene: &LineScene) -> Image {
    let cpu_image = cpu::render(scene);
    let gpu_image = renderer
        .render(scene)
        .unwrap_or_else(|e| panic!("{name}: GPU render failed: {e}"));
    assert_eq!(
        (gpu_image.width, gpu_image.height, gpu_image.pixels.len()),
        (
            scene.width,
            scene.height,
            (scene.width * scene.height * 4) as usize
        ),
        "{name}: GPU image size"
    );
    let colours: Vec<Rgba> = scene.batches.iter().map(|b| b.color).collect();
    for (backend, image) in [("cpu", &cpu_image), ("gpu", &gpu_image)] {
        if let Some(p) = image
            .pixels
            .chunks_exact(4)
            .find(|p| *p != scene.background && !colours.iter().any(|c| c == p))
        {
            panic!("{name}: {backend} pixel {p:?} is neither background nor a line colour");
        }
    }
    let cpu_lit = lit_mask(&cpu_image, scene.background);
    let gpu_lit = lit_mask(&gpu_image, scene.background);
    let (cpu_near, cpu_count) = agreement(&cpu_lit, &gpu_lit, scene.width, scene.height);
    let (gpu_near, gpu_count) = agreement(&gpu_lit, &cpu_lit, scene.width, scene.height);
    let exact = cpu_lit
        .iter()
        .zip(&gpu_lit)
        .filter(|(a, b)| **a && **b)
        .count();
    eprintln!(
        "{name}: {}x{}, {} segments; lit cpu {cpu_count} gpu {gpu_count}, same pixel {exact}; \
         within 1 px: cpu→gpu {:.2} %, gpu→cpu {:.2} %",
        scene.width,
        scene.height,
        scene.segment_count(),
        100.0 * cpu_near,
        100.0 * gpu_near
    );
    if cpu_near < MIN_AGREEMENT || gpu_near < MIN_AGREEMENT {
        let dir = std::env::temp_dir();
        let (c, g) = (
            dir.join(format!("wireflight-{name}-cpu.png")),
            dir.join(format!("wireflight-{name}-gpu.png")),
        );
        std::fs::write(&c, cpu_image.encode_png().unwrap()).unwrap();
        std::fs::write(&g, gpu_image.encode_png().unwrap()).unwrap();
        panic!(
            "{name}: backends disagree (cpu→gpu {cpu_near:.4}, gpu→cpu {gpu_near:.4}, need \
             {MIN_AGREEMENT}); images in {} and {}",
            c.display(),
            g.display()
        );
    }
    assert!(cpu_count > 0, "{name}: the scene draws nothing");
    gpu_image
}

fn plane_spec(yaw: f64, pitch: f64, roll: f64, camera: CameraPreset, size: (u32, u32)) -> ViewSpec {
    ViewSpec {
        attitude: EulerZyx::from_degrees(yaw, pitch, roll),
        camera,
        viewport: Viewport {
            width: size.0,
            height: size.1,
        },
        ..ViewSpec::default()
    }
}

#[test]
fn plane_at_several_attitudes_and_cameras_matches_the_cpu() {
    let Some(mut gpu) = gpu() else { return };
    let plane = builtin_plane();
    let cases = [
        (
            "level_chase",
            plane_spec(0.0, 0.0, 0.0, CameraPreset::Chase, (800, 600)),
        ),
        (
            "banked_chase",
            plane_spec(30.0, -15.0, 40.0, CameraPreset::Chase, (800, 600)),
        ),
        (
            "front",
            plane_spec(-20.0, 10.0, -25.0, CameraPreset::Front, (640, 480)),
        ),
        (
            "top",
            plane_spec(45.0, 0.0, 0.0, CameraPreset::Top, (640, 480)),
        ),
        (
            "side",
            plane_spec(0.0, -30.0, 0.0, CameraPreset::Side, (1280, 720)),
        ),
        (
            "cockpit",
            plane_spec(10.0, 5.0, 20.0, CameraPreset::Cockpit, (1280, 720)),
        ),
        (
            "gimbal_lock",
            plane_spec(0.0, 90.0, 30.0, CameraPreset::Chase, (800, 600)),
        ),
        (
            "ortho_side",
            ViewSpec {
                orthographic: true,
                ..plane_spec(0.0, 0.0, 15.0, CameraPreset::Side, (800, 600))
            },
        ),
        (
            "half_out_of_frame",
            ViewSpec {
                pan: [1.0, 0.3],
                ..plane_spec(15.0, -5.0, 10.0, CameraPreset::Chase, (800, 600))
            },
        ),
    ];
    for (name, spec) in cases {
        let (scene, _) = frame(&plane, &spec);
        assert_backends_agree(name, &mut gpu, &scene);
    }
}

/// A small deterministic generator (SplitMix64) for test geometry.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// A point on the image border (the clipper's output for lines crossing the frame), sometimes
/// exactly on the far edges x = width or y = height.
fn border_point(rng: &mut SplitMix, width: u32, height: u32) -> Vec2 {
    let (w, h) = (width as f32, height as f32);
    let t = rng.unit();
    match rng.next() % 4 {
        0 => Vec2::new(t * w, 0.0),
        1 => Vec2::new(t * w, h),
        2 => Vec2::new(0.0, t * h),
        _ => Vec2::new(w, t * h),
    }
}

/// Long lines from border to border in three colours, plus shorter ones inside the frame.
fn crossing_lines(width: u32, height: u32, lines: usize, seed: u64) -> LineScene {
    let mut rng = SplitMix(seed);
    let colours: [Rgba; 3] = [palette::GRID, [255, 200, 60, 255], palette::AIRCRAFT];
    let batches = colours
        .iter()
        .map(|&color| LineBatch {
            color,
            segments: (0..lines / 3)
                .map(|i| {
                    if i % 4 == 3 {
                        let (w, h) = (width as f32, height as f32);
                        Segment2 {
                            a: Vec2::new(rng.unit() * w, rng.unit() * h),
                            b: Vec2::new(rng.unit() * w, rng.unit() * h),
                        }
                    } else {
                        Segment2 {
                            a: border_point(&mut rng, width, height),
                            b: border_point(&mut rng, width, height),
                        }
                    }
                })
                .collect(),
        })
        .collect();
    LineScene {
        width,
        height,
        background: palette::BACKGROUND,
        batches,
    }
}

#[test]
fn many_long_lines_crossing_the_frame_match_the_cpu() {
    let Some(mut gpu) = gpu() else { return };
    assert_backends_agree(
        "crossing_lines",
        &mut gpu,
        &crossing_lines(1280, 720, 300, 7),
    );
    // Frame edges: lines along all four borders, the far ones exactly at x = width, y = height
    // (both backends clamp them into the last column / row).
    let (w, h) = (400.0, 300.0);
    let corners = [
        Vec2::new(0.0, 0.0),
        Vec2::new(w, 0.0),
        Vec2::new(w, h),
        Vec2::new(0.0, h),
    ];
    let border = LineScene {
        width: 400,
        height: 300,
        background: palette::BACKGROUND,
        batches: vec![LineBatch {
            color: palette::AIRCRAFT,
            segments: (0..4)
                .map(|i| Segment2 {
                    a: corners[i],
                    b: corners[(i + 1) % 4],
                })
                .collect(),
        }],
    };
    let image = assert_backends_agree("frame_border", &mut gpu, &border);
    let lit = |x, y| image.pixel(x, y) == palette::AIRCRAFT;
    let right = (1..299).filter(|&y| lit(399, y)).count();
    let bottom = (1..399).filter(|&x| lit(x, 299)).count();
    assert!(
        right >= 297 && bottom >= 397,
        "far edges: {right} / {bottom} lit"
    );
}

#[test]
fn later_batches_are_drawn_on_top() {
    let Some(mut gpu) = gpu() else { return };
    let line = Segment2 {
        a: Vec2::new(10.5, 20.5),
        b: Vec2::new(90.5, 20.5),
    };
    let scene = LineScene {
        width: 100,
        height: 40,
        background: [0, 0, 0, 255],
        batches: vec![
            LineBatch {
                color: [255, 0, 0, 255],
                segments: vec![line],
            },
            LineBatch {
                color: [1, 254, 127, 128],
                segments: vec![line],
            },
        ],
    };
    let image = gpu.render(&scene).unwrap();
    for x in 11..90 {
        assert_eq!(image.pixel(x, 20), [1, 254, 127, 128], "pixel ({x}, 20)");
    }
}

/// Widths that are not multiples of 64 pixels (256 bytes) need padded readback rows; getting the
/// padding wrong shears the image, which both checks below would catch.
#[test]
fn readback_strips_row_padding() {
    let Some(mut gpu) = gpu() else { return };
    let (width, height) = (333, 201);
    // One horizontal line on row 100 and vertical lines on the first and last columns.
    let scene = LineScene {
        width,
        height,
        background: palette::BACKGROUND,
        batches: vec![LineBatch {
            color: palette::AIRCRAFT,
            segments: vec![
                Segment2 {
                    a: Vec2::new(0.0, 100.5),
                    b: Vec2::new(333.0, 100.5),
                },
                Segment2 {
                    a: Vec2::new(0.5, 0.0),
                    b: Vec2::new(0.5, 201.0),
                },
                Segment2 {
                    a: Vec2::new(333.0, 0.0),
                    b: Vec2::new(333.0, 201.0),
                },
            ],
        }],
    };
    let image = assert_backends_agree("padding_lines_333x201", &mut gpu, &scene);
    for y in 0..height {
        let row: Vec<u32> = (0..width)
            .filter(|&x| image.pixel(x, y) == palette::AIRCRAFT)
            .collect();
        if y == 100 {
            assert!(
                row.len() >= width as usize - 1,
                "row 100: {} lit",
                row.len()
            );
        } else if y > 0 && y < height - 1 {
            assert_eq!(row, [0, width - 1], "row {y}");
        }
    }
    // The plane at the same odd size, then at another size and back: the resized frame buffers
    // must give the same picture as the first time.
    let spec = plane_spec(30.0, -15.0, 40.0, CameraPreset::Chase, (width, height));
    let (plane_scene, _) = frame(&builtin_plane(), &spec);
    let first = assert_backends_agree("plane_333x201", &mut gpu, &plane_scene);
    let (other, _) = frame(
        &builtin_plane(),
        &plane_spec(0.0, 0.0, 0.0, CameraPreset::Top, (257, 64)),
    );
    assert_backends_agree("plane_257x64", &mut gpu, &other);
    let again = gpu.render(&plane_scene).unwrap();
    assert!(first == again, "the same frame after a resize differs");
}

#[test]
fn empty_scene_is_the_background() {
    let Some(mut gpu) = gpu() else { return };
    let scene = LineScene {
        width: 65,
        height: 3,
        background: [8, 12, 24, 255],
        batches: vec![LineBatch {
            color: palette::AIRCRAFT,
            segments: vec![],
        }],
    };
    assert_eq!(
        gpu.render(&scene).unwrap(),
        Image::filled(65, 3, [8, 12, 24, 255])
    );
}

#[test]
fn cli_renders_on_the_gpu_and_names_the_adapter() {
    let adapter = match gpu() {
        Some(renderer) => renderer.adapter().name.clone(),
        None => return,
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let o = wireflight(&[
        "render",
        "--backend",
        "gpu",
        "--size",
        "333x201",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    eprintln!("wireflight render --backend gpu: stderr: {stderr}");
    assert!(o.status.success(), "{stderr}");
    assert!(
        stderr.contains("GPU: ") && stderr.contains(&adapter),
        "stderr does not name the adapter {adapter:?}: {stderr}"
    );
    // Mesa's device-selection layer is kept quiet where there is no runtime directory.
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
    let image = Image::decode_png(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!((image.width, image.height), (333, 201));
    let lit = image
        .pixels
        .chunks_exact(4)
        .filter(|p| *p == palette::AIRCRAFT)
        .count();
    assert!(lit > 100, "only {lit} model pixels");
}
