pub mod obj;
pub mod svg;
