//! Log directory/file names and the `ctime` date text of the banner.

use chrono::NaiveDateTime;

/// pLogger's log root name: `<stem>_D_M_YYYY_____HH_MM_SS` (day and month not padded, time
/// fields two digits), or just `stem` when `time_stamp` is false (`FileTimeStamp=false`).
/// The directory and every file of a session share this root (`<root>/<root>.alog`).
///
/// ```
/// use chrono::NaiveDate;
/// let t = NaiveDate::from_ymd_opt(2026, 8, 5).unwrap().and_hms_opt(18, 2, 5).unwrap();
/// assert_eq!(alog::log_root("LOG_ALPHA", &t, true), "LOG_ALPHA_5_8_2026_____18_02_05");
/// assert_eq!(alog::log_root("LOG_ALPHA", &t, false), "LOG_ALPHA");
/// ```
pub fn log_root(stem: &str, at: &NaiveDateTime, time_stamp: bool) -> String {
    if !time_stamp {
        return stem.to_string();
    }
    format!("{stem}_{}", at.format("%-d_%-m_%Y_____%H_%M_%S"))
}

/// The C `ctime` text of a date-time without its trailing newline, as in the banner's
/// `FILE OPENED ON` line: `Wed Aug  5 18:22:55 2026` (day of month space-padded).
///
/// ```
/// use chrono::NaiveDate;
/// let t = NaiveDate::from_ymd_opt(1970, 1, 1).unwrap().and_hms_opt(0, 0, 0).unwrap();
/// assert_eq!(alog::ctime(&t), "Thu Jan  1 00:00:00 1970");
/// ```
pub fn ctime(at: &NaiveDateTime) -> String {
    at.format("%a %b %e %H:%M:%S %Y").to_string()
}
