//! The script parser of `wireflight view` and the modules it uses.
#[path = "../../../../../src/app/view/cameras.rs"]
pub mod cameras;
#[path = "../../../../../src/app/view/flight.rs"]
pub mod flight;
#[path = "../../../../../src/app/view/script.rs"]
pub mod script;
