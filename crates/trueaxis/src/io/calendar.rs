//! Dates of the proleptic Gregorian calendar from a count of days since 1970-01-01 (the Unix epoch),
//! for the times written into logs and reports: H. Hinnant, "chrono-compatible low-level date
//! algorithms", `civil_from_days` (eras of 400 years = 146 097 days, years starting on 1 March so
//! that the leap day ends them).

/// The date (year, month 1 ... 12, day 1 ... 31) of the day `days` after 1970-01-01 (negative:
/// before it).
pub fn civil_from_days(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z - era * 146_097;
    let year_of_era = (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let mp = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    (year_of_era + era * 400 + i64::from(month <= 2), month, day)
}
