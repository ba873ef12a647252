//! The fly-through window's panels that run the analysis, without a window: the compare panel
//! of `wireflight view --compare` and its discover. A [`compare::Compare`] joins the viewer's
//! session (`wireflight_draw::flythrough::session`) as its model panel.

pub mod compare;
pub mod discovery;
