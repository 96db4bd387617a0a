//! alignment (in progress).
