//! Small commands that only print what wireflight knows: `keys`.

pub mod keys;
