//! The one error type of the core. Variants carry the numbers that explain them, so that the binding
//! layer can turn them into Python exceptions with expected-versus-actual messages.

/// Errors raised by the numerical core on user input or geometry; the core never panics on user input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// An argument has the wrong shape, e.g. `expected baselines of shape (m, 3), got (2,)`.
    #[error("expected {name} of shape {expected}, got {actual}")]
    Shape {
        name: &'static str,
        expected: String,
        actual: String,
    },
    /// An argument holds NaN or infinity.
    #[error("{name} contains a non-finite value at index {index}")]
    NonFinite { name: &'static str, index: usize },
    /// An argument is finite but outside its valid range.
    #[error("{name} is out of range: {detail}")]
    OutOfRange { name: &'static str, detail: String },
    /// The geometry does not determine the answer: a singular or near-singular matrix.
    #[error("{what}: the {matrix} has condition number {condition:.3e}")]
    DegenerateGeometry {
        what: String,
        matrix: &'static str,
        condition: f64,
    },
    /// A scalar that the answer divides by is zero or too small, e.g. `cos(pitch)` or the sine of the
    /// angle between two TRIAD vectors; `quantity` names it, `value` is what it was.
    #[error("{what}: {quantity} is {value:.3e}, needs to exceed {limit:.1e}")]
    Degenerate {
        what: String,
        quantity: &'static str,
        value: f64,
        limit: f64,
    },
    /// An iterative method did not converge.
    #[error("{what} did not converge after {iterations} iterations")]
    Convergence {
        what: &'static str,
        iterations: usize,
    },
    /// A user-controlled amount of work or memory (candidates, samples, steps, cells) exceeds its documented
    /// limit; checked before any work starts.
    #[error("{name} asks for {requested} {unit}, more than the limit of {limit}")]
    TooLarge {
        name: &'static str,
        requested: f64,
        limit: f64,
        unit: &'static str,
    },
    /// A computation on valid input lost its accuracy (overflow, a failed identity check, a diverging
    /// integration) and refuses to return a wrong answer; `detail` carries the numbers.
    #[error("{what}: {detail}")]
    Numerical { what: &'static str, detail: String },
    /// The caller asked to stop (Ctrl-C) while the computation ran.
    #[error("{what} interrupted")]
    Interrupted { what: &'static str },
}

/// Result alias used throughout the core.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// The same error, said to have happened at epoch `k` of a batch.
    pub fn at_epoch(self, k: usize) -> Self {
        match self {
            Error::DegenerateGeometry {
                what,
                matrix,
                condition,
            } => Error::DegenerateGeometry {
                what: format!("epoch {k}: {what}"),
                matrix,
                condition,
            },
            Error::Degenerate {
                what,
                quantity,
                value,
                limit,
            } => Error::Degenerate {
                what: format!("epoch {k}: {what}"),
                quantity,
                value,
                limit,
            },
            Error::OutOfRange { name, detail } => Error::OutOfRange {
                name,
                detail: format!("epoch {k}: {detail}"),
            },
            other => other,
        }
    }

    pub fn too_large(name: &'static str, requested: f64, limit: f64, unit: &'static str) -> Self {
        Error::TooLarge {
            name,
            requested,
            limit,
            unit,
        }
    }

    pub fn numerical(what: &'static str, detail: impl Into<String>) -> Self {
        Error::Numerical {
            what,
            detail: detail.into(),
        }
    }

    pub(crate) fn out_of_range(name: &'static str, detail: impl Into<String>) -> Self {
        Error::OutOfRange {
            name,
            detail: detail.into(),
        }
    }
}

/// Checks that every value is finite, naming the argument and the flat index of the first bad value.
pub fn ensure_finite<'a>(
    name: &'static str,
    values: impl IntoIterator<Item = &'a f64>,
) -> Result<()> {
    match values.into_iter().position(|v| !v.is_finite()) {
        Some(index) => Err(Error::NonFinite { name, index }),
        None => Ok(()),
    }
}
