//! spring_damper element (in progress).
