//! Scenes that compose the natura crates into images.
