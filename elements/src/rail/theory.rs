//! theory (in progress).
