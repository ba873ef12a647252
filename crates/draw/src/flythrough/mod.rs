//! The fly-through window's state without a window: what `wireflight view` shows, driven
//! by keys, a script or a recorded flight, computed here so that it can be tested (and
//! drawn offscreen) without a display. The window itself (winit, egui, the wgpu surface) is
//! the binary's.

pub mod cameras;
pub mod compare;
pub mod discovery;
pub mod flight;
pub mod gimbal;
pub mod script;
pub mod session;
