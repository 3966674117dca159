//! Translating KRL programs to other robot languages.

pub mod orientation;
