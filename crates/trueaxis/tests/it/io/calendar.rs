//! `io::calendar` against GNU `date -u -d @SECONDS +%Y-%m-%d` of the same days: the epoch, the day
//! before it, a 400-year leap day's March, a leap day, the first day of the era count, the last day
//! of year 9999.

use trueaxis::io::calendar::civil_from_days;

#[test]
fn days_since_the_epoch_give_the_dates_gnu_date_gives() {
    for (days, date) in [
        (0, (1970, 1, 1)),
        (-1, (1969, 12, 31)),
        (11_017, (2000, 3, 1)),
        (19_782, (2024, 2, 29)),
        (-719_468, (0, 3, 1)),
        (2_932_896, (9999, 12, 31)),
    ] {
        assert_eq!(civil_from_days(days), date, "day {days}");
    }
}
