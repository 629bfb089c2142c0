//! Mitsuba 3's `spectrum` values in its RGB variants: a list of `wavelength:value` pairs
//! is turned into linear sRGB exactly as `scalar_rgb` does when it loads a scene
//! (`spectrum_list_to_srgb` in Mitsuba's `src/core/spectrum.cpp`):
//!
//! - 1000 wavelengths evenly spaced over the CIE range, 360 nm to 830 nm inclusive, each
//!   weighted by the CIE 1931 2° colour matching functions (tabulated every 5 nm,
//!   linearly interpolated) and by the spectrum, linearly interpolated between its
//!   points and zero outside its first and last wavelength;
//! - the sum times `(830 − 360) / 1000` and Mitsuba's normalisation `1 / ∫ȳ`
//!   (`MI_CIE_Y_NORMALIZATION`), giving CIE XYZ, then XYZ → linear sRGB;
//! - reflectances are also weighted by the CIE D65 illuminant (normalised so that a flat
//!   reflectance of 1 is white) and clamped to `[0, 1]`; emitter spectra are neither.
//!
//! A single value (`value="0.5"`) is a uniform spectrum: the value itself for a
//! reflectance, and for an emitter the colour of a flat spectrum of that height, which
//! is not grey in sRGB (`(1.2048, 0.9483, 0.9089)` for 1: sRGB's white is D65, not equal
//! energy). Checked against Mitsuba 3.9.1 (`mitsuba.spectrum_list_to_srgb`, and the
//! values `scalar_rgb` puts in its textures) in this file's tests.

/// Shortest and longest wavelength of the CIE tables, nm (`MI_CIE_MIN`, `MI_CIE_MAX`).
const CIE_MIN: f64 = 360.0;
const CIE_MAX: f64 = 830.0;
/// `1 / ∫ȳ(λ) dλ` over the table, as Mitsuba defines it (`MI_CIE_Y_NORMALIZATION`).
const CIE_Y_NORMALIZATION: f64 = 0.009367658735689113;
/// Wavelengths Mitsuba integrates over.
const STEPS: usize = 1000;

/// CIE 1931 2° standard observer, x̄ ȳ z̄ at 5 nm from 360 nm to 830 nm (the CIE's
/// published table, in the single precision Mitsuba stores it in).
const CIE_1931: [[f32; 3]; 95] = [
    [0.0001299, 0.000003917, 0.0006061],  // 360 nm
    [0.0002321, 0.000006965, 0.001086],   // 365 nm
    [0.0004149, 0.00001239, 0.001946],    // 370 nm
    [0.0007416, 0.00002202, 0.003486],    // 375 nm
    [0.001368, 0.000039, 0.006450001],    // 380 nm
    [0.002236, 0.000064, 0.01054999],     // 385 nm
    [0.004243, 0.00012, 0.02005001],      // 390 nm
    [0.00765, 0.000217, 0.03621],         // 395 nm
    [0.01431, 0.000396, 0.06785001],      // 400 nm
    [0.02319, 0.00064, 0.1102],           // 405 nm
    [0.04351, 0.00121, 0.2074],           // 410 nm
    [0.07763, 0.00218, 0.3713],           // 415 nm
    [0.13438, 0.004, 0.6456],             // 420 nm
    [0.21477, 0.0073, 1.0390501],         // 425 nm
    [0.2839, 0.0116, 1.3856],             // 430 nm
    [0.3285, 0.01684, 1.62296],           // 435 nm
    [0.34828, 0.023, 1.74706],            // 440 nm
    [0.34806, 0.0298, 1.7826],            // 445 nm
    [0.3362, 0.038, 1.77211],             // 450 nm
    [0.3187, 0.048, 1.7441],              // 455 nm
    [0.2908, 0.06, 1.6692],               // 460 nm
    [0.2511, 0.0739, 1.5281],             // 465 nm
    [0.19536, 0.09098, 1.28764],          // 470 nm
    [0.1421, 0.1126, 1.0419],             // 475 nm
    [0.09564, 0.13902, 0.8129501],        // 480 nm
    [0.05795001, 0.1693, 0.6162],         // 485 nm
    [0.03201, 0.20802, 0.46518],          // 490 nm
    [0.0147, 0.2586, 0.3533],             // 495 nm
    [0.0049, 0.323, 0.272],               // 500 nm
    [0.0024, 0.4073, 0.2123],             // 505 nm
    [0.0093, 0.503, 0.1582],              // 510 nm
    [0.0291, 0.6082, 0.1117],             // 515 nm
    [0.06327, 0.71, 0.07824999],          // 520 nm
    [0.1096, 0.7932, 0.05725001],         // 525 nm
    [0.1655, 0.862, 0.04216],             // 530 nm
    [0.2257499, 0.9148501, 0.02984],      // 535 nm
    [0.2904, 0.954, 0.0203],              // 540 nm
    [0.3597, 0.9803, 0.0134],             // 545 nm
    [0.4334499, 0.9949501, 0.008749999],  // 550 nm
    [0.5120501, 1.0, 0.005749999],        // 555 nm
    [0.5945, 0.995, 0.0039],              // 560 nm
    [0.6784, 0.9786, 0.002749999],        // 565 nm
    [0.7621, 0.952, 0.0021],              // 570 nm
    [0.8425, 0.9154, 0.0018],             // 575 nm
    [0.9163, 0.87, 0.001650001],          // 580 nm
    [0.9786, 0.8163, 0.0014],             // 585 nm
    [1.0263, 0.757, 0.0011],              // 590 nm
    [1.0567, 0.6949, 0.001],              // 595 nm
    [1.0622, 0.631, 0.0008],              // 600 nm
    [1.0456, 0.5668, 0.0006],             // 605 nm
    [1.0026, 0.503, 0.00034],             // 610 nm
    [0.9384, 0.4412, 0.00024],            // 615 nm
    [0.8544499, 0.381, 0.00019],          // 620 nm
    [0.7514, 0.321, 0.0001],              // 625 nm
    [0.6424, 0.265, 0.00004999999],       // 630 nm
    [0.5419, 0.217, 0.00003],             // 635 nm
    [0.4479, 0.175, 0.00002],             // 640 nm
    [0.3608, 0.1382, 0.00001],            // 645 nm
    [0.2835, 0.107, 0.0],                 // 650 nm
    [0.2187, 0.0816, 0.0],                // 655 nm
    [0.1649, 0.061, 0.0],                 // 660 nm
    [0.1212, 0.04458, 0.0],               // 665 nm
    [0.0874, 0.032, 0.0],                 // 670 nm
    [0.0636, 0.0232, 0.0],                // 675 nm
    [0.04677, 0.017, 0.0],                // 680 nm
    [0.0329, 0.01192, 0.0],               // 685 nm
    [0.0227, 0.00821, 0.0],               // 690 nm
    [0.01584, 0.005723, 0.0],             // 695 nm
    [0.01135916, 0.004102, 0.0],          // 700 nm
    [0.008110916, 0.002929, 0.0],         // 705 nm
    [0.005790346, 0.002091, 0.0],         // 710 nm
    [0.004109457, 0.001484, 0.0],         // 715 nm
    [0.002899327, 0.001047, 0.0],         // 720 nm
    [0.00204919, 0.00074, 0.0],           // 725 nm
    [0.001439971, 0.00052, 0.0],          // 730 nm
    [0.0009999493, 0.0003611, 0.0],       // 735 nm
    [0.0006900786, 0.0002492, 0.0],       // 740 nm
    [0.0004760213, 0.0001719, 0.0],       // 745 nm
    [0.0003323011, 0.00012, 0.0],         // 750 nm
    [0.0002348261, 0.0000848, 0.0],       // 755 nm
    [0.0001661505, 0.00006, 0.0],         // 760 nm
    [0.000117413, 0.0000424, 0.0],        // 765 nm
    [0.00008307527, 0.00003, 0.0],        // 770 nm
    [0.00005870652, 0.0000212, 0.0],      // 775 nm
    [0.00004150994, 0.00001499, 0.0],     // 780 nm
    [0.00002935326, 0.0000106, 0.0],      // 785 nm
    [0.00002067383, 0.0000074657, 0.0],   // 790 nm
    [0.00001455977, 0.0000052578, 0.0],   // 795 nm
    [0.00001025398, 0.0000037029, 0.0],   // 800 nm
    [0.000007221456, 0.0000026078, 0.0],  // 805 nm
    [0.000005085868, 0.0000018366, 0.0],  // 810 nm
    [0.000003581652, 0.0000012934, 0.0],  // 815 nm
    [0.000002522525, 0.00000091093, 0.0], // 820 nm
    [0.000001776509, 0.00000064153, 0.0], // 825 nm
    [0.000001251141, 0.00000045181, 0.0], // 830 nm
];

/// CIE standard illuminant D65 at 5 nm from 360 nm to 830 nm, times Mitsuba's
/// `MI_CIE_D65_NORMALIZATION` (as its `cie_d65` returns it).
const CIE_D65: [f32; 95] = [
    0.47110626, 0.49863625, 0.52616626, 0.51549125, 0.5048162, 0.5284158, 0.55201644, 0.69397265, 0.8359299, 0.880027,
    0.92412513, 0.9339526, 0.9437802, 0.9096904, 0.8756016, 0.9674353, 1.05927, 1.1205949, 1.1819298, 1.1859906,
    1.1900512, 1.1751418, 1.1602424, 1.1656061, 1.17097, 1.1350498, 1.0991297, 1.1018672, 1.1046146, 1.0967761,
    1.0889375, 1.073725, 1.0585124, 1.0731492, 1.0877961, 1.0712098, 1.0546235, 1.0528052, 1.0509971, 1.0305623,
    1.0101273, 0.99161273, 0.9730981, 0.9703394, 0.9675808, 0.9317092, 0.89583755, 0.9025074, 0.9091773, 0.9071206,
    0.905065, 0.8954668, 0.88586855, 0.86359423, 0.84132093, 0.8433947, 0.8454686, 0.82692057, 0.8083726, 0.8093211,
    0.8102696, 0.8206901, 0.8311106, 0.8109403, 0.7907702, 0.7475215, 0.70427394, 0.71380854, 0.72334313, 0.7371808,
    0.7510196, 0.68664926, 0.62227887, 0.6641062, 0.7059336, 0.7322039, 0.7584743, 0.70042026, 0.6423673, 0.5556246,
    0.46888295, 0.5718513, 0.6748196, 0.65753335, 0.64024705, 0.64489967, 0.6495523, 0.6250456, 0.6005399, 0.5626955,
    0.5248521, 0.5525376, 0.58022326, 0.59472764, 0.6092331,
];

/// CIE XYZ to linear sRGB (Rec. 709 primaries, D65 white), as Mitsuba's `xyz_to_srgb`.
const XYZ_TO_SRGB: [[f64; 3]; 3] =
    [[3.240479, -1.537150, -0.498535], [-0.969256, 1.875991, 0.041556], [0.055648, -0.204043, 1.057311]];

/// Where `lambda` nm falls in the 5 nm tables: index of the sample below, and the
/// weight of the one above; `None` outside the tables.
fn table_position(lambda: f64) -> Option<(usize, f64)> {
    if !(CIE_MIN..=CIE_MAX).contains(&lambda) {
        return None;
    }
    let t = (lambda - CIE_MIN) / 5.0;
    let i = (t.floor() as usize).min(CIE_1931.len() - 2);
    Some((i, t - i as f64))
}

/// The colour matching functions at `lambda` nm (zero outside the table).
fn cie_xyz(lambda: f64) -> [f64; 3] {
    let Some((i, w)) = table_position(lambda) else { return [0.0; 3] };
    let (a, b) = (CIE_1931[i], CIE_1931[i + 1]);
    [0, 1, 2].map(|c| a[c] as f64 * (1.0 - w) + b[c] as f64 * w)
}

/// The normalised D65 illuminant at `lambda` nm (zero outside the table).
fn d65(lambda: f64) -> f64 {
    let Some((i, w)) = table_position(lambda) else { return 0.0 };
    CIE_D65[i] as f64 * (1.0 - w) + CIE_D65[i + 1] as f64 * w
}

/// Linear sRGB of the piecewise-linear spectrum through `points` (`(nm, value)`, in
/// increasing wavelength; at least one). `reflectance` weights it by D65 and clamps the
/// result to `[0, 1]`, as Mitsuba does for everything but emitters.
pub(crate) fn spectrum_to_srgb(points: &[(f64, f64)], reflectance: bool) -> [f32; 3] {
    let mut xyz = [0.0f64; 3];
    let (Some(first), Some(last)) = (points.first(), points.last()) else { return [0.0; 3] };
    for i in 0..STEPS {
        let x = CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN);
        if x < first.0 || x > last.0 {
            continue;
        }
        // The interval [x0, x1] holding x (the last one when x is the last point).
        let k = points.partition_point(|p| p.0 <= x).clamp(1, points.len().max(2) - 1);
        let y = if points.len() == 1 {
            first.1
        } else {
            let ((x0, y0), (x1, y1)) = (points[k - 1], points[k]);
            if x1 > x0 {
                y0 + (y1 - y0) * (x - x0) / (x1 - x0)
            } else {
                y0
            }
        };
        let c = cie_xyz(x);
        let illuminant = if reflectance { d65(x) } else { 1.0 };
        for j in 0..3 {
            xyz[j] += c[j] * y * illuminant;
        }
    }
    let scale = (CIE_MAX - CIE_MIN) / STEPS as f64 * CIE_Y_NORMALIZATION;
    let xyz = xyz.map(|v| v * scale);
    XYZ_TO_SRGB.map(|row| {
        let v = row[0] * xyz[0] + row[1] * xyz[1] + row[2] * xyz[2];
        (if reflectance { v.clamp(0.0, 1.0) } else { v }) as f32
    })
}

/// A uniform spectrum of height `v`: `v` as a reflectance, and as an emitter's
/// spectrum the sRGB colour of a flat spectrum over the CIE range.
pub(crate) fn uniform_to_srgb(v: f64, emitter: bool) -> [f32; 3] {
    if emitter {
        spectrum_to_srgb(&[(CIE_MIN, v), (CIE_MAX, v)], false)
    } else {
        [v as f32; 3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f32; 3], b: [f32; 3], rel: f32) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= rel * y.abs().max(1e-3))
    }

    /// Mitsuba 3.9.1, `scalar_rgb`: the Cornell box's light
    /// (`mi.spectrum_list_to_srgb([400, 500, 600, 700], [0, 8, 15.6, 18.4], False)`).
    #[test]
    fn cornell_light_matches_mitsuba() {
        let c = spectrum_to_srgb(&[(400.0, 0.0), (500.0, 8.0), (600.0, 15.6), (700.0, 18.4)], false);
        assert!(close(c, [20.7108, 10.8546, 2.77115], 2e-5), "{c:?}");
        // Bounded (as a reflectance would be), every channel clamps to 1.
        let b = spectrum_to_srgb(&[(400.0, 0.0), (500.0, 8.0), (600.0, 15.6), (700.0, 18.4)], true);
        assert_eq!(b, [1.0, 1.0, 1.0]);
    }

    /// The first points of the Cornell box's white wall, as Mitsuba puts them in its
    /// `SRGBReflectanceSpectrum` (`400:0.343, 404:0.445, 408:0.551, 700:0.737`).
    #[test]
    fn reflectance_matches_mitsuba() {
        let c = spectrum_to_srgb(&[(400.0, 0.343), (404.0, 0.445), (408.0, 0.551), (700.0, 0.737)], true);
        assert!(close(c, [0.696929, 0.636909, 0.568497], 2e-5), "{c:?}");
    }

    #[test]
    fn uniform_spectra() {
        assert_eq!(uniform_to_srgb(0.5, false), [0.5; 3]);
        let e = uniform_to_srgb(1.0, true);
        // Mitsuba's own value for `<spectrum value="1"/>` in an emitter differs from its
        // `spectrum_list_to_srgb([360, 830], [1, 1])` = (1.20488, 0.948229, 0.909267),
        // which this equals, by up to 4e-4 relative (it takes another path for one value).
        assert!(close(e, [1.20479, 0.948291, 0.908916], 5e-4), "{e:?}");
        assert!(close(e, [1.20488, 0.948229, 0.909267], 2e-5), "{e:?}");
    }
}
