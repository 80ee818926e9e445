//! Linear sRGB radiometric triple (W/(m^2 sr) per channel for radiance).

use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Sub};

/// A linear sRGB colour (radiance, reflectance, ...) in f32.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Rgb {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
}

impl Rgb {
    /// Black.
    pub const ZERO: Rgb = Rgb::splat(0.0);
    /// White (1, 1, 1).
    pub const ONE: Rgb = Rgb::splat(1.0);

    /// The colour (r, g, b).
    pub const fn new(r: f32, g: f32, b: f32) -> Self {
        Rgb { r, g, b }
    }
    /// The grey (v, v, v).
    pub const fn splat(v: f32) -> Self {
        Rgb { r: v, g: v, b: v }
    }
    /// The colour `m` makes of this one (a colour space's or a film's linear map).
    pub fn transformed(self, m: glam::Mat3) -> Self {
        let v = m * glam::Vec3::new(self.r, self.g, self.b);
        Rgb::new(v.x, v.y, v.z)
    }
    /// Whether every channel is zero.
    pub fn is_black(self) -> bool {
        self.r == 0.0 && self.g == 0.0 && self.b == 0.0
    }
    /// Whether every channel is finite.
    pub fn is_finite(self) -> bool {
        self.r.is_finite() && self.g.is_finite() && self.b.is_finite()
    }
    /// The largest channel.
    pub fn max_component(self) -> f32 {
        self.r.max(self.g).max(self.b)
    }
    /// Rec. 709 luminance.
    pub fn luminance(self) -> f32 {
        0.2126 * self.r + 0.7152 * self.g + 0.0722 * self.b
    }
    /// The mean of the channels.
    pub fn average(self) -> f32 {
        (self.r + self.g + self.b) / 3.0
    }
    /// `f` applied to each channel.
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Rgb::new(f(self.r), f(self.g), f(self.b))
    }
    /// The channels as [r, g, b].
    pub fn to_array(self) -> [f32; 3] {
        [self.r, self.g, self.b]
    }
}

impl From<[f32; 3]> for Rgb {
    fn from(a: [f32; 3]) -> Self {
        Rgb::new(a[0], a[1], a[2])
    }
}

impl Add for Rgb {
    type Output = Rgb;
    fn add(self, o: Rgb) -> Rgb {
        Rgb::new(self.r + o.r, self.g + o.g, self.b + o.b)
    }
}
impl Sub for Rgb {
    type Output = Rgb;
    fn sub(self, o: Rgb) -> Rgb {
        Rgb::new(self.r - o.r, self.g - o.g, self.b - o.b)
    }
}
impl AddAssign for Rgb {
    fn add_assign(&mut self, o: Rgb) {
        *self = *self + o;
    }
}
impl Mul for Rgb {
    type Output = Rgb;
    fn mul(self, o: Rgb) -> Rgb {
        Rgb::new(self.r * o.r, self.g * o.g, self.b * o.b)
    }
}
impl MulAssign for Rgb {
    fn mul_assign(&mut self, o: Rgb) {
        *self = *self * o;
    }
}
impl Mul<f32> for Rgb {
    type Output = Rgb;
    fn mul(self, s: f32) -> Rgb {
        Rgb::new(self.r * s, self.g * s, self.b * s)
    }
}
impl Mul<Rgb> for f32 {
    type Output = Rgb;
    fn mul(self, c: Rgb) -> Rgb {
        c * self
    }
}
impl MulAssign<f32> for Rgb {
    fn mul_assign(&mut self, s: f32) {
        *self = *self * s;
    }
}
impl Div<f32> for Rgb {
    type Output = Rgb;
    fn div(self, s: f32) -> Rgb {
        self * (1.0 / s)
    }
}
