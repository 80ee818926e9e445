//! Where the sun stands at a date, time and place: NOAA's solar position calculation (after
//! Meeus, Astronomical Algorithms, 1991; NOAA Global Monitoring Laboratory's solar
//! calculator), good to about a minute of arc between 1800 and 2100, without refraction.

/// A moment given as a civil date and time with its offset from UTC.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moment {
    year: i32,
    month: u32,
    day: u32,
    /// Hours, minutes and seconds of the local time.
    hour: u32,
    minute: u32,
    second: f64,
    /// Local time minus UTC, in minutes.
    utc_offset_min: i32,
}

/// Text that names no moment (a date and time with its UTC offset).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("expected a date and time with its UTC offset, as 2026-06-21T15:30+02:00 or 2026-06-21T13:30Z, got \"{0}\"")]
pub struct NotAMoment(pub String);

impl Moment {
    /// Parses `YYYY-MM-DDTHH:MM[:SS](Z|+HH:MM|-HH:MM)` (RFC 3339; a space may stand for the
    /// T). The offset is required: a time without one names no moment.
    pub fn parse(text: &str) -> Result<Moment, NotAMoment> {
        let bad = || NotAMoment(text.to_string());
        let (date, rest) = text.split_once(['T', ' ']).ok_or_else(bad)?;
        let mut d = date.splitn(3, '-');
        let next_num = |what: &mut std::str::SplitN<char>| -> Result<i64, NotAMoment> {
            what.next().and_then(|v| v.parse().ok()).ok_or_else(bad)
        };
        let (year, month, day) = (next_num(&mut d)?, next_num(&mut d)?, next_num(&mut d)?);
        let (clock, offset) = if let Some(c) = rest.strip_suffix(['Z', 'z']) {
            (c, 0)
        } else {
            let at = rest.rfind(['+', '-']).ok_or_else(bad)?;
            let (c, o) = rest.split_at(at);
            let sign = if o.starts_with('-') { -1 } else { 1 };
            let (h, m) = o[1..].split_once(':').ok_or_else(bad)?;
            let (h, m): (i32, i32) = (h.parse().map_err(|_| bad())?, m.parse().map_err(|_| bad())?);
            if h > 18 || m > 59 {
                return Err(bad());
            }
            (c, sign * (h * 60 + m))
        };
        let mut c = clock.split(':');
        let hour: u32 = c.next().and_then(|v| v.parse().ok()).ok_or_else(bad)?;
        let minute: u32 = c.next().and_then(|v| v.parse().ok()).ok_or_else(bad)?;
        let second: f64 = match c.next() {
            Some(s) => s.parse().map_err(|_| bad())?,
            None => 0.0,
        };
        let valid = (1..=12).contains(&month)
            && (1..=days_in_month(year as i32, month as u32) as i64).contains(&day)
            && hour < 24
            && minute < 60
            && (0.0..61.0).contains(&second)
            && c.next().is_none();
        if !valid {
            return Err(bad());
        }
        Ok(Moment {
            year: year as i32,
            month: month as u32,
            day: day as u32,
            hour,
            minute,
            second,
            utc_offset_min: offset,
        })
    }

    /// Julian date (days since noon UTC, 1 January 4713 BC).
    pub fn julian_date(&self) -> f64 {
        let days = days_from_civil(self.year, self.month, self.day) as f64;
        let seconds = (self.hour * 3600 + self.minute * 60) as f64 + self.second
            - (self.utc_offset_min * 60) as f64;
        // 1970-01-01T00:00Z is Julian date 2440587.5.
        2_440_587.5 + days + seconds / 86_400.0
    }
}

fn is_leap(y: i32) -> bool {
    (y % 4 == 0 && y % 100 != 0) || y % 400 == 0
}

fn days_in_month(y: i32, m: u32) -> u32 {
    match m {
        2 if is_leap(y) => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// Days from 1970-01-01 to the civil date (proleptic Gregorian calendar).
fn days_from_civil(y: i32, m: u32, d: u32) -> i64 {
    let y = if m <= 2 { y - 1 } else { y } as i64;
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m as i64 + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d as i64 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// The sun's elevation above the horizon and its azimuth clockwise from north (degrees) at
/// `moment` seen from `latitude_deg` (north positive) and `longitude_deg` (east positive).
pub fn sun_position(moment: &Moment, latitude_deg: f64, longitude_deg: f64) -> (f64, f64) {
    let jd = moment.julian_date();
    let t = (jd - 2451545.0) / 36525.0;
    let mean_long = (280.46646 + t * (36000.76983 + t * 0.0003032)).rem_euclid(360.0);
    let mean_anom = 357.52911 + t * (35999.05029 - 0.0001537 * t);
    let ecc = 0.016708634 - t * (0.000042037 + 0.0000001267 * t);
    let m = mean_anom.to_radians();
    let center = m.sin() * (1.914602 - t * (0.004817 + 0.000014 * t))
        + (2.0 * m).sin() * (0.019993 - 0.000101 * t)
        + (3.0 * m).sin() * 0.000289;
    let true_long = mean_long + center;
    let omega = (125.04 - 1934.136 * t).to_radians();
    let apparent_long = (true_long - 0.00569 - 0.00478 * omega.sin()).to_radians();
    let mean_obliq =
        23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60.0) / 60.0;
    let obliq = (mean_obliq + 0.00256 * omega.cos()).to_radians();
    let declination = (obliq.sin() * apparent_long.sin()).asin();
    let y = (obliq / 2.0).tan().powi(2);
    let l0 = mean_long.to_radians();
    // Equation of time, minutes.
    let eq_time = 4.0
        * (y * (2.0 * l0).sin() - 2.0 * ecc * m.sin() + 4.0 * ecc * y * m.sin() * (2.0 * l0).cos()
            - 0.5 * y * y * (4.0 * l0).sin()
            - 1.25 * ecc * ecc * (2.0 * m).sin())
        .to_degrees();
    let utc_minutes = ((jd + 0.5).fract()) * 1440.0;
    let solar_minutes = (utc_minutes + eq_time + 4.0 * longitude_deg).rem_euclid(1440.0);
    let hour_angle = (solar_minutes / 4.0 - 180.0).to_radians();
    let lat = latitude_deg.to_radians();
    let cos_zenith = (lat.sin() * declination.sin()
        + lat.cos() * declination.cos() * hour_angle.cos())
    .clamp(-1.0, 1.0);
    let zenith = cos_zenith.acos();
    let elevation = 90.0 - zenith.to_degrees();
    // Azimuth from north, clockwise; from the sun's east-west and north-south components.
    let east = -declination.cos() * hour_angle.sin();
    let north = declination.sin() * lat.cos() - declination.cos() * lat.sin() * hour_angle.cos();
    let azimuth = east.atan2(north).to_degrees().rem_euclid(360.0);
    (elevation, azimuth)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str) -> Moment {
        Moment::parse(text).expect("a moment")
    }

    #[test]
    fn julian_dates_of_known_moments() {
        // J2000.0 is 2000-01-01T12:00 TT; 1970-01-01T00:00Z is 2440587.5.
        assert_eq!(at("2000-01-01T12:00Z").julian_date(), 2_451_545.0);
        assert_eq!(at("1970-01-01T02:00+02:00").julian_date(), 2_440_587.5);
        assert_eq!(at("1969-12-31 19:00:00-05:00").julian_date(), 2_440_587.5);
    }

    #[test]
    fn the_sun_where_the_almanac_puts_it() {
        // Noon at the June solstice on the Tropic of Cancer's meridian through Greenwich:
        // overhead within the equation of time's few minutes.
        let (el, _) = sun_position(&at("2026-06-21T12:00Z"), 23.44, 0.0);
        assert!(el > 89.0, "{el}");
        // The equinox at the equator at sunrise: on the horizon, due east.
        let (el, az) = sun_position(&at("2026-03-20T06:07Z"), 0.0, 0.0);
        assert!(el.abs() < 0.6 && (az - 90.0).abs() < 1.0, "{el} {az}");
        // NREL's solar position algorithm (Reda and Andreas 2004, as pvlib 0.16.1 computes it,
        // without refraction): elevation and azimuth in degrees.
        for (moment, lat, lon, el_ref, az_ref) in [
            ("2010-06-21T12:00-06:00", 40.0, -105.0, 68.921, 137.165),
            ("2026-06-21T16:00+02:00", 48.85, 2.35, 54.301, 236.171),
            ("2026-12-21T16:00+11:00", -33.87, 151.21, 48.057, 271.737),
        ] {
            let (el, az) = sun_position(&at(moment), lat, lon);
            let close = (el - el_ref).abs() < 0.03 && (az - az_ref).abs() < 0.05;
            assert!(close, "{moment}: {el} {az}, SPA {el_ref} {az_ref}");
        }
    }

    #[test]
    fn bad_moments_are_refused_with_the_expected_form() {
        for bad in [
            "2026-06-21T15:00",
            "2026-02-30T12:00Z",
            "2026-06-21",
            "2026-13-01T00:00Z",
            "2026-06-21T25:00Z",
            "noon",
        ] {
            let e = Moment::parse(bad).expect_err("refused").to_string();
            assert!(
                e.contains("2026-06-21T15:30+02:00") && e.contains(bad),
                "{e}"
            );
        }
    }
}
