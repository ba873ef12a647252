//! The geometry of wireflight, pure: no files, no GPU, no window.
//!
//! Data flows one way: a model ([`mesh`]) is turned ([`euler`]) and viewed ([`camera`]) into
//! homogeneous clip space, clipped there ([`clip`], Blinn's clipper by default), divided by w
//! and mapped to pixels ([`pipeline`]), and leaves as coloured 2D segments ([`lines`]) that
//! every backend of the drawing crate can draw.

#![warn(missing_docs)]

pub mod camera;
pub mod clip;
pub mod euler;
pub mod lines;
pub mod mesh;
pub mod pipeline;
