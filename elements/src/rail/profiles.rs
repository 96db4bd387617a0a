//! profiles (in progress).
