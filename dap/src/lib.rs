//! The debug adapter (filled by the DAP work).
