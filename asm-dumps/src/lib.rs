//! Probe functions for assembly inspection.
