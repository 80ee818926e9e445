//! Averages an image over k x k pixel blocks (a box filter), keeping its mean: how the small
//! reference images of the real-scene tests are made from full-size renders.
//!
//! cargo run --release -p fenestra-core --example box_downsample -- IN.exr OUT.exr K

use fenestra_core::image::Image;
use fenestra_core::Rgb;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output, k] = &args[..] else {
        return Err("usage: box_downsample IN OUT K".into());
    };
    let k: usize = k.parse()?;
    let img = Image::read(Path::new(input))?;
    if k == 0 || img.width % k != 0 || img.height % k != 0 {
        return Err(format!("{}x{} is not a multiple of {k}", img.width, img.height).into());
    }
    let mut out = Image::new(img.width / k, img.height / k);
    for y in 0..out.height {
        for x in 0..out.width {
            let mut sum = Rgb::ZERO;
            for dy in 0..k {
                for dx in 0..k {
                    sum += img.get(x * k + dx, y * k + dy);
                }
            }
            out.set(x, y, sum / (k * k) as f32);
        }
    }
    out.write_exr(Path::new(output), &Default::default())?;
    println!("{input} -> {output}: {}x{}", out.width, out.height);
    Ok(())
}
