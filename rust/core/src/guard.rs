//! The two guards every long computation of the core applies to user-sized work: the amount of work is
//! checked against a documented limit before anything starts ([`check_work`]), and what comes out is
//! checked to be finite before it is returned ([`finite_output`]); interruption is in [`crate::interrupt`].

use crate::error::{Error, Result};

/// Refuses `requested` units of work above `limit` with [`Error::TooLarge`] naming the parameter `name`.
///
/// `requested` is a float so that products of user sizes (epochs x steps) are formed without overflow;
/// NaN is refused too.
///
/// # Errors
/// [`Error::TooLarge`] when `requested > limit` or `requested` is NaN.
pub fn check_work(
    name: &'static str,
    requested: f64,
    limit: f64,
    unit: &'static str,
) -> Result<()> {
    if requested <= limit {
        Ok(())
    } else {
        Err(Error::too_large(name, requested, limit, unit))
    }
}

/// Refuses a computed result holding NaN or infinity with [`Error::Numerical`]: `what` names the
/// computation, the message the first bad flat index and `hint`, what to change.
///
/// # Errors
/// [`Error::Numerical`] for the first non-finite value.
pub fn finite_output<'a>(
    what: &'static str,
    values: impl IntoIterator<Item = &'a f64>,
    hint: &str,
) -> Result<()> {
    match values.into_iter().position(|v| !v.is_finite()) {
        Some(index) => Err(Error::numerical(
            what,
            format!("the result is not finite (first at flat index {index}); {hint}"),
        )),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_work_refuses_above_the_limit_and_nan() {
        assert_eq!(check_work("n", 10.0, 10.0, "steps"), Ok(()));
        assert_eq!(
            check_work("n", 11.0, 10.0, "steps"),
            Err(Error::too_large("n", 11.0, 10.0, "steps"))
        );
        assert!(check_work("n", f64::NAN, 10.0, "steps").is_err());
    }

    #[test]
    fn finite_output_names_the_first_bad_index() {
        assert_eq!(finite_output("x", &[1.0, 2.0], "h"), Ok(()));
        let e = finite_output("x", &[1.0, f64::NAN, f64::INFINITY], "h").unwrap_err();
        assert!(e.to_string().contains("flat index 1"), "{e}");
    }
}
