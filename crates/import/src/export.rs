//! Scenes written for other renderers: what strata renders, from the flattened records, so that
//! the other renderer draws the same image (as far as it can express it) and the two can be
//! compared pixel by pixel.

pub mod mitsuba;
