//! beam3d element (in progress).
