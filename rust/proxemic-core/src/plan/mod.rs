//! Grid path planning.
