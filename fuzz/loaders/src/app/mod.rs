//! The view's script parser and what it names.
pub mod view;
