//! The modelling phase (paper §3.1), pure math: catenaries between pins, the
//! surface approximation, and relaxation into a rest shape.

pub mod catenary;
