// Lines of a `LineScene` (src/render/gpu.rs): pixel coordinates in, flat colour out.
//
// Vertices are in the scene's pixel convention (origin top-left, y down, pixel (i, j) covers
// [i, i+1)×[j, j+1)). Like the CPU backend, an endpoint lands in pixel (⌊x⌋, ⌊y⌋) clamped into
// the image, so the vertex is snapped to that pixel's centre before the NDC transform
// x_ndc = 2x/W − 1, y_ndc = 1 − 2y/H; both backends then start and end every line in the same
// pixels and differ only in how they step between them.

struct Viewport {
    // Image width and height, pixels.
    size: vec2<f32>,
    // Padding to the 16-byte uniform block size.
    _pad: vec2<f32>,
}

@group(0) @binding(0) var<uniform> viewport: Viewport;

struct VertexOut {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) color: vec4<f32>,
}

@vertex
fn vs_main(@location(0) pixel: vec2<f32>, @location(1) color: vec4<f32>) -> VertexOut {
    let centre = clamp(floor(pixel), vec2<f32>(0.0), viewport.size - 1.0) + 0.5;
    let ndc = vec2<f32>(
        2.0 * centre.x / viewport.size.x - 1.0,
        1.0 - 2.0 * centre.y / viewport.size.y,
    );
    var out: VertexOut;
    out.position = vec4<f32>(ndc, 0.0, 1.0);
    out.color = color;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return in.color;
}
