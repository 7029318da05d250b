//! Tables of values against time (`[t, v₁, v₂, …]` rows): validated with errors that
//! name the row, and read linearly in between, held before the first row and after the
//! last. A body's temperature history and a rigid body's velocity history are such tables.

use crate::input::InputError;

/// Checks that `rows` (at `key` in the input) is not empty, that every entry is finite
/// and that the times (first column) increase strictly. `row` names a row in the
/// messages, e.g. `"[time, temperature] pair"`.
pub fn validate<const N: usize>(key: &str, rows: &[[f64; N]], row: &str) -> Result<(), InputError> {
    if rows.is_empty() {
        return Err(InputError::new(
            key,
            "[]",
            format!("need at least one {row}"),
        ));
    }
    for (k, r) in rows.iter().enumerate() {
        if !r.iter().all(|x| x.is_finite()) {
            return Err(InputError::new(
                format!("{key}[{k}]"),
                format!("{r:?}"),
                "every entry must be finite",
            ));
        }
        if k > 0 && r[0] <= rows[k - 1][0] {
            return Err(InputError::new(
                format!("{key}[{k}]"),
                format!("{r:?}"),
                format!(
                    "times must increase strictly: {} follows {}",
                    r[0],
                    rows[k - 1][0]
                ),
            ));
        }
    }
    Ok(())
}

/// The row at time `t` of a validated table: linear between rows, the first row before
/// the first time and the last after the last (the time entry is `t` itself inside).
pub fn at<const N: usize>(rows: &[[f64; N]], t: f64) -> [f64; N] {
    let k = rows.partition_point(|r| r[0] <= t);
    if k == 0 {
        return rows[0];
    }
    if k == rows.len() {
        return rows[k - 1];
    }
    let (a, b) = (&rows[k - 1], &rows[k]);
    let f = (t - a[0]) / (b[0] - a[0]);
    std::array::from_fn(|j| a[j] + (b[j] - a[j]) * f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_holds_and_names_the_row() {
        let rows = [[1.0, 0.0, 2.0], [3.0, 4.0, 0.0]];
        assert!(validate("v", &rows, "[t, vx, vy] row").is_ok());
        assert_eq!(at(&rows, 0.0), [1.0, 0.0, 2.0]);
        assert_eq!(at(&rows, 2.0), [2.0, 2.0, 1.0]);
        assert_eq!(at(&rows, 9.0), [3.0, 4.0, 0.0]);
        let e = validate("body[2].velocity_table", &[[1.0, 0.0], [1.0, 1.0]], "pair").unwrap_err();
        assert_eq!(e.key, "body[2].velocity_table[1]");
        assert_eq!(e.value, "[1.0, 1.0]");
        let e = validate::<2>("t", &[], "[time, temperature] pair").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t = []: need at least one [time, temperature] pair"
        );
        let e = validate("t", &[[0.0, f64::NAN]], "pair").unwrap_err();
        assert_eq!(e.key, "t[0]");
    }
}
