//! Height-field synthesis: stochastic subdivision (lines, triangles, quads,
//! diamond-square) and B-spline surfaces on its points, Poisson faulting, successive random additions, Fourier
//! synthesis and noise synthesis from any scalar field; terraces of
//! quantised altitude.

pub mod bspline;
pub mod dla;
pub mod fault;
pub mod field;
pub mod mesh;
pub mod spectral;
pub mod sra;
pub mod subdivision;
pub mod terrace;

pub use bspline::{bspline_surface, cubic_bspline_weights};
pub use dla::{MAX_DLA_PARTICLES, dla};
pub use fault::{FaultParams, poisson_faults};
pub use field::{FieldMapping, fill_field, fill_noise, fill_rows};
pub use mesh::{TriMesh, subdivide_mesh, subdivide_mesh_until};
pub use spectral::{SpectralParams, spectral_synthesis};
pub use sra::{SraParams, successive_random_additions};
pub use subdivision::{
    EndpointMode, MidpointParams, SubdivisionParams, SubdivisionScheme, fractal_polyline,
    fractal_polyline_ids, midpoint_1d, subdivide,
};
pub use terrace::{TerraceParams, terrace};
