pub mod obj;
pub mod surface_svg;
pub mod svg;
