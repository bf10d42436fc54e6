//! `uvflat methods`: the names and one-line descriptions of the methods of `uvflat unwrap
//! --method`, and the option values that choose a method's variant.

use clap::ValueEnum;
use uvflat_core::methods::nonlinear::NonlinearMethod;

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum MethodName {
    Tutte,
    Floater,
    Authalic,
    Conformal,
    MeanValue,
    Intrinsic,
    NaturalConformal,
    Slim,
    Arap,
    Mips,
    Stretch,
    GreenLagrange,
    Degener,
    Abf,
    #[value(name = "abf++")]
    AbfPlusPlus,
    SpectralConformal,
    CirclePatterns,
    IntrinsicOptimal,
    BoundaryOptimized,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum EnergyName {
    /// Edge-length distortion Σ (|u_i − u_j|²/|x_i − x_j|² − 1)².
    Edge,
    /// Area distortion Σ ((A_uv/A_3D)² − 1)².
    Area,
}

impl MethodName {
    /// The distortion-minimizing method, for the free-boundary non-linear methods.
    pub(crate) fn nonlinear(self) -> Option<NonlinearMethod> {
        Some(match self {
            MethodName::Slim => NonlinearMethod::Slim,
            MethodName::Arap => NonlinearMethod::Arap,
            MethodName::Mips => NonlinearMethod::Mips,
            MethodName::Stretch => NonlinearMethod::Stretch,
            MethodName::GreenLagrange => NonlinearMethod::GreenLagrange,
            MethodName::Degener => NonlinearMethod::Degener,
            _ => return None,
        })
    }
}

/// Each method's CLI name and one-line description, as `uvflat methods` prints them.
pub(crate) const METHODS: [(MethodName, &str, &str); 19] = [
    (MethodName::Tutte, "tutte", "fixed boundary, uniform weights (Tutte 1963); never flips with a convex boundary"),
    (MethodName::Floater, "floater", "fixed boundary, Floater's shape-preserving weights (1997); never flips"),
    (MethodName::Authalic, "authalic", "fixed boundary, discrete authalic = Wachspress (Desbrun et al. 2002 eq. 6)"),
    (MethodName::Conformal, "conformal", "fixed boundary, discrete conformal = harmonic (Desbrun et al. 2002 eq. 4)"),
    (MethodName::MeanValue, "mean-value", "fixed boundary, mean value weights (Floater 2003); never flips"),
    (MethodName::Intrinsic, "intrinsic", "fixed boundary, lambda*DCP + mu*DAP (Desbrun et al. 2002 §3.4)"),
    (
        MethodName::NaturalConformal,
        "natural-conformal",
        "free boundary, natural conformal map = LSCM (Desbrun et al. 2002 eq. 7); the default",
    ),
    (MethodName::Slim, "slim", "free boundary, symmetric Dirichlet by SLIM (Rabinovich et al. 2017); never flips"),
    (MethodName::Arap, "arap", "free boundary, as-rigid-as-possible local-global (Liu et al. 2008); never flips, no triangle below 1% of its share of the area"),
    (MethodName::Mips, "mips", "free boundary, MIPS conformal energy (Hormann & Greiner 2000); never flips"),
    (MethodName::Stretch, "stretch", "free boundary, L2 stretch (Sander et al. 2001); never flips"),
    (
        MethodName::GreenLagrange,
        "green-lagrange",
        "free boundary, Green-Lagrange tensor (Maillot et al. 1993); never flips, no triangle below 1% of its share of the area",
    ),
    (MethodName::Degener, "degener", "free boundary, Degener et al. 2003 angle x area^theta energy; never flips"),
    (MethodName::Abf, "abf", "free boundary, angle based flattening, full Newton (Sheffer & de Sturler 2001)"),
    (MethodName::AbfPlusPlus, "abf++", "free boundary, ABF++ Gauss-Newton + LSCM reconstruction (Sheffer et al. 2005)"),
    (
        MethodName::SpectralConformal,
        "spectral-conformal",
        "free boundary, conformal without pins: smallest generalized eigenvector (Mullen et al. 2008)",
    ),
    (
        MethodName::CirclePatterns,
        "circle-patterns",
        "conformal by circle patterns on the intrinsic Delaunay triangulation (Kharevych et al. 2006); free, polygon (--corner) or convex (--convex-boundary) boundary; cones (--cone, --auto-cones) on any genus",
    ),
    (
        MethodName::IntrinsicOptimal,
        "intrinsic-optimal",
        "fixed boundary, lambda*DCP map + (1-lambda)*DAP map of least --energy (Desbrun et al. 2002 §5.1)",
    ),
    (
        MethodName::BoundaryOptimized,
        "boundary-optimized",
        "intrinsic map whose boundary descends --energy, never flipping (Desbrun et al. 2002 §5.2)",
    ),
];

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum DistributionName {
    Uniform,
    Chord,
    Centripetal,
}

pub(crate) fn list_methods() {
    for (_, name, description) in METHODS {
        println!("{name:<18} {description}");
    }
}

pub(crate) fn method_label(method: MethodName) -> &'static str {
    METHODS.iter().find(|(m, _, _)| *m == method).map_or("?", |(_, name, _)| name)
}
