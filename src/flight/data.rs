//! Flight data: the CSV format of `shared/specs/flight-data.md`.
