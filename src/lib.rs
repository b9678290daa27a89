//! Host package for the workspace tests and examples.
