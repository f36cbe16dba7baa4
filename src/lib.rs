//! hysteron
