//! wgpu offscreen line renderer.
