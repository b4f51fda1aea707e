//! The animation phase (paper §3.2–3.3): arrives with the animation work.
