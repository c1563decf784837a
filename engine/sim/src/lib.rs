//! The glider simulator (filled by the simulator work).
