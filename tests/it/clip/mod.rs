//! The clipping lab: Blinn's clipper against a brute-force reference and a 3D frustum, every
//! algorithm on the seeds' worked examples, all of them cross-validated on random and
//! adversarial edges, Blinn's batch paths held to the per-edge clipper, extra planes,
//! bounding-sphere and back-face rejection, the `clip` command (edges and Weiler-Atherton's
//! polygons), and the fuzz corpus replayed.

mod agree;
mod batch;
mod blinn;
mod blinn_property;
pub(crate) mod check;
mod command;
mod corpus;
mod extra;
pub(crate) mod polygons;
mod reference;
mod regress;
mod seeds;
