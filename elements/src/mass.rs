//! mass element (in progress).
