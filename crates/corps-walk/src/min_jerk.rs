//! The min-jerk blend every smooth transition of a walk uses (CoM height over a step, the
//! swing's height, the start of a walk off the middle of the feet).

pub(crate) use corps_model::min_jerk::min_jerk_between as min_jerk;
