//! The articulated progressive mesh of a character (Houle & Poulin 2001) and the discrete LOD chain
//! extracted from it.

pub mod poses;
