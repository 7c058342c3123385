//! placeholder during development
pub mod geom;
pub mod quadrature;
pub mod solid_angle;
