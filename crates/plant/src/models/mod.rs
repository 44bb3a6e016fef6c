//! The source papers' plant models.
