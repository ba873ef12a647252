//! The fly-through window's state without a window: what `wireflight view` shows, driven
//! by keys, a script or a recorded flight, computed here so that it can be tested (and
//! drawn offscreen) without a display. The window itself (winit, egui, the wgpu surface) is
//! the binary's; the compare panel, which runs the analysis, is `wireflight-present`'s and
//! joins a [`session::Session`] as its [`session::ModelPanel`].

pub mod cameras;
pub mod flight;
pub mod gimbal;
pub mod script;
pub mod session;
