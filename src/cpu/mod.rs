//! The CPU side of the contract, in double precision and independent of the
//! shaders. Today: the lighting formula (the twin of
//! `shaders/include/lighting.glsl`). The CPU reference renderer grows here.

pub mod lighting;
