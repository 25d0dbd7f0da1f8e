//! The shading model: the local illumination at a hit and the secondary rays it
//! spawns, with their weights. Three models, chosen by the scene's dialect.
//!
//! Both share the form of the local term. For a hit with material
//! `(C, Kd, S, Ks, shine, T, ior)` (`S`, the specular colour, is white in NFF), facing
//! normal `n` (the geometric normal turned towards the incoming ray), shading normal
//! `ns`, view direction `v = -d` and lights of intensity `I_l` sampled at points `p_j`
//! (one for a point light, `M` for an area light, see `light.rs`):
//!
//! ```text
//! colour = A * Ka                                                      ambient (Ka = Kd * C but in AFF)
//!        + sum over lights, over their points with dot(n, l_j) > 0, unshadowed:
//!            I_l / M * (Kd * C * max(0, ns.l_j) + Ks * S * c_j^shine)  Lambert + highlight
//!        + secondary rays (below)
//! ```
//!
//! The highlight's cosine `c_j` (clamped to [0, 1]) is the model's: NFF's is
//! Blinn-Phong's `ns.h_j`, `h_j = normalize(l_j + v)` (the SPD's); P3F's is Phong's
//! `r_j.v`, `r_j = 2 (ns.l_j) ns - l_j` the light's mirror direction. The course's
//! texts name Blinn-Phong, but its pictures have Phong's narrower highlights: against
//! `reference/p3f/balls_low-whitted.png` the mean difference per channel falls from
//! 4.96/4.19/5.11 with `ns.h` to 3.51/2.83/4.13 with `r.v` (P3F-SPEC).
//!
//! **NFF (the SPD's Whitted rules)**: every hit on a surface with `Ks > 0` or `T > 0`
//! spawns a mirror ray of weight `Ks`, and one with `T > 0` a refracted ray of weight
//! `T` (Snell, `ior` entering and `1/ior` leaving; `ior <= 0` means 1); under total
//! internal reflection the mirror ray carries `Ks + T`. `A` and every uncoloured light
//! have intensity `sqrt(n) / (2n)` for n lights (`A = 1` without lights).
//!
//! **P3F (the course's)**: lights have their colours as intensities and there is no
//! ambient term (`A = 0`). The colour a secondary ray returns is clamped to 1 in each
//! channel before the hit that spawned it weights it, as the course's template does:
//! its pictures show the over-exposed yellow floor reflected pale in the spheres of
//! `2025/balls_low.p3f`, and the clamp takes the mean difference from the course's
//! Whitted picture from 3.53/2.84/4.15 to 2.25/1.90/4.13 levels of 255. An opaque surface (`T = 0`) with `Ks > 0` spawns a mirror
//! ray of weight `Ks * S`. A transmissive one (`T > 0`) spawns a mirror ray of weight
//! `R * S` and a refracted ray of weight `(1 - R) * T`, where `R` is Schlick's
//! approximation of the Fresnel reflectance ([`schlick`]), 1 under total internal
//! reflection. Inside, the glass absorbs by Beer-Lambert with the coefficient
//! `1 - C` per unit length (its diffuse colour `C`, as the course's glass "uses the
//! diffuse colour for the absorption"): a ray that travels `d` inside brings back
//! `exp(-(1 - C) d)` of what it meets. A rough surface (`roughness` above 0) reflects
//! and refracts about microfacet normals drawn per ray ([`Facets`],
//! [`super::microfacet`]); a direction that would leave on the wrong side of the
//! surface is mirrored across it.
//!
//! **AFF (BART's original renderer, tuituji/bart `Scene::Radiance` in
//! `src/scene.cpp`)**: `fm`'s colours enter as they are: the ambient reflectance
//! `Ka` is `fm`'s ambient colour (0 for `f`), `A` the scene's `am` (white by
//! default), `Kd * C` the diffuse colour and `Ks * S` the specular colour; lights
//! have their colours as intensities and the highlight is Blinn-Phong's, as in NFF.
//! Every hit spawns a mirror ray of weight `Ks * S * (1 - T)`, and one with
//! `T > 0` a refracted ray of weight `T` (`ior` entering, 1 leaving); under total
//! internal reflection the mirror ray carries the `T` too. A textured surface's
//! whole colour, its secondary rays' included, is multiplied by its texel, and the
//! colour a secondary ray returns is clamped to 1 in each channel, as the original
//! clamps each ray's colour.

use crate::math::Vec3;
use crate::prepare::lighting::Model;
use crate::scene::Material;

use super::optics::{reflect, refract, schlick};

/// The kind of a secondary ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Branch {
    /// Mirror reflection.
    Reflection,
    /// Mirror reflection under total internal reflection (carries the transmitted share).
    TotalInternalReflection,
    /// Refraction.
    Refraction,
}

/// The local term of a unit-intensity light in unit direction `l` under the rules
/// `M`: Lambert on `diffuse` (`Kd * C`) plus the highlight `Ks * S * c^shine`, `c`
/// the model's highlight cosine ([`Rules::highlight_cosine`]).
#[inline]
pub fn local<M: Rules>(m: &Material, diffuse: Vec3, ns: Vec3, l: Vec3, view: Vec3) -> Vec3 {
    let lambert = ns.dot(l).max(0.0);
    // A negative exponent would turn a zero cosine into infinity, and a cosine that
    // rounds above 1 a huge exponent (shine 1e30) into infinity too.
    let highlight = if m.ks > 0.0 {
        let c = M::highlight_cosine(ns, l, view);
        m.ks * c.clamp(0.0, 1.0).powf(m.shine.max(0.0))
    } else {
        0.0
    };
    diffuse * lambert + m.specular * highlight
}

/// The secondary rays of a hit: the refracted ray's direction and weight, and the
/// mirror ray's kind, weight and direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Secondary {
    /// Direction and weight of the refracted ray.
    pub refraction: Option<(Vec3, Vec3)>,
    /// Kind, weight and direction of the mirror ray.
    pub reflection: Option<(Branch, Vec3, Vec3)>,
}

/// The surface normals a hit's secondary rays leave about: the facing normal itself
/// on a smooth surface; on a rough one, a microfacet normal drawn for each ray
/// ([`super::microfacet`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facets {
    /// The normal the mirror ray reflects about.
    pub reflection: Vec3,
    /// The normal the refracted ray refracts through.
    pub refraction: Vec3,
}

impl Facets {
    /// A smooth surface of facing normal `n`.
    pub fn smooth(n: Vec3) -> Facets {
        Facets {
            reflection: n,
            refraction: n,
        }
    }
}

/// The rules of one model for the secondary rays of a hit: a type per model, so the
/// recursion is compiled once per model and pays for no choice at every hit.
pub trait Rules {
    /// The secondary rays of a hit on `m` by unit direction `d`, with unit normal
    /// `n` facing the ray, leaving about `facets`; `entering` says whether the ray
    /// crosses into the object.
    fn secondary(m: &Material, d: Vec3, n: Vec3, entering: bool, facets: &Facets) -> Secondary;

    /// The cosine whose power `shine` is the highlight of a light in unit direction
    /// `l` seen from unit direction `view` on the unit shading normal `ns` (see the
    /// module docs; not clamped).
    fn highlight_cosine(ns: Vec3, l: Vec3, view: Vec3) -> f32;

    /// The colour a secondary ray returns to the hit that spawned it, given the
    /// colour at its end (see the module docs).
    fn returned(color: Vec3) -> Vec3;

    /// The absorption coefficient per unit length inside a transmissive `m`, if it
    /// absorbs (see the module docs); none but in P3F.
    #[inline(always)]
    fn absorption(_m: &Material) -> Option<Vec3> {
        None
    }

    /// True if the rules draw rough directions for `m` (its roughness above 0);
    /// never but in P3F (NFF and AFF have no roughness).
    #[inline(always)]
    fn is_rough(_m: &Material) -> bool {
        false
    }

    /// The normals a smooth surface of facing geometric normal `n` and shading
    /// normal `ns` sends its secondary rays about: `n` but in AFF, whose original
    /// reflects and refracts about the interpolated normal.
    #[inline(always)]
    fn smooth_facets(n: Vec3, _ns: Vec3) -> Facets {
        Facets::smooth(n)
    }

    /// What `m` reflects of the ambient light, given its `diffuse` colour `Kd * C`:
    /// the diffuse colour but in AFF (see the module docs).
    #[inline(always)]
    fn ambient_reflectance(_m: &Material, diffuse: Vec3) -> Vec3 {
        diffuse
    }
}

/// [`Model::Spd`]'s rules.
pub struct SpdRules;

/// [`Model::P3f`]'s rules.
pub struct P3fRules;

/// [`Model::Aff`]'s rules.
pub struct AffRules;

/// The indices of refraction on the incident and the transmitted side (`ior <= 0`,
/// seen on opaque materials, means 1).
#[inline(always)]
fn indices(m: &Material, entering: bool) -> (f32, f32) {
    let ior = if m.ior > 0.0 { m.ior } else { 1.0 };
    if entering {
        (1.0, ior)
    } else {
        (ior, 1.0)
    }
}

/// `dir` on the side of the unit normal `n` that `above` says (`dir.n > 0` above,
/// `< 0` below): as it is when it already is, else mirrored across the surface. A
/// direction drawn about a microfacet normal can point to the wrong side of the
/// surface itself; folding it back keeps it near the facet's direction.
#[inline(always)]
fn on_side(dir: Vec3, n: Vec3, above: bool) -> Vec3 {
    let c = dir.dot(n);
    if (c > 0.0) == above {
        dir
    } else {
        dir - n * (2.0 * c)
    }
}

impl Rules for SpdRules {
    /// Blinn-Phong: `ns.h`, `h` the half vector.
    #[inline(always)]
    fn highlight_cosine(ns: Vec3, l: Vec3, view: Vec3) -> f32 {
        ns.dot((l + view).normalize())
    }

    /// As it is: the SPD's rules clamp only the pixel.
    #[inline(always)]
    fn returned(color: Vec3) -> Vec3 {
        color
    }

    #[inline(always)]
    fn secondary(m: &Material, d: Vec3, n: Vec3, entering: bool, _: &Facets) -> Secondary {
        if m.ks <= 0.0 && m.t <= 0.0 {
            return Secondary {
                refraction: None,
                reflection: None,
            };
        }
        whitted_split(m, d, n, entering, Vec3::splat(m.ks))
    }
}

/// The Whitted split of the SPD's and AFF's rules: a mirror ray of weight `mirror`
/// and, for `T > 0`, a refracted ray of weight `T` (Snell, [`indices`]); under total
/// internal reflection the mirror ray carries the `T` too.
#[inline(always)]
fn whitted_split(m: &Material, d: Vec3, n: Vec3, entering: bool, mirror: Vec3) -> Secondary {
    let mut weight = mirror;
    let mut kind = Branch::Reflection;
    let mut refraction = None;
    if m.t > 0.0 {
        let (n1, n2) = indices(m, entering);
        match refract(d, n, n1 / n2) {
            Some(dir) => refraction = Some((dir, Vec3::splat(m.t))),
            // Total internal reflection: the transmitted share goes to the mirror ray.
            None => {
                weight += Vec3::splat(m.t);
                kind = Branch::TotalInternalReflection;
            }
        }
    }
    Secondary {
        refraction,
        reflection: Some((kind, weight, reflect(d, n))),
    }
}

impl Rules for P3fRules {
    /// Phong: `r.v`, `r` the light's mirror direction about `ns`.
    #[inline(always)]
    fn highlight_cosine(ns: Vec3, l: Vec3, view: Vec3) -> f32 {
        (ns * (2.0 * ns.dot(l)) - l).dot(view)
    }

    /// Clamped to 1 in each channel, as the course's pictures show it.
    #[inline(always)]
    fn returned(color: Vec3) -> Vec3 {
        color.min(Vec3::ONE)
    }

    /// `1 - C` (at least 0) for a transmissive material with a colour other than
    /// white: Beer-Lambert absorption inside.
    #[inline(always)]
    fn absorption(m: &Material) -> Option<Vec3> {
        m.absorption()
    }

    #[inline(always)]
    fn is_rough(m: &Material) -> bool {
        m.roughness > 0.0 && (m.ks > 0.0 || m.t > 0.0)
    }

    #[inline(always)]
    fn secondary(m: &Material, d: Vec3, n: Vec3, entering: bool, facets: &Facets) -> Secondary {
        let mirror = |about: Vec3| on_side(reflect(d, about), n, true);
        if m.t <= 0.0 {
            return Secondary {
                refraction: None,
                reflection: (m.ks > 0.0)
                    .then(|| (Branch::Reflection, m.specular * m.ks, mirror(facets.reflection))),
            };
        }
        let (n1, n2) = indices(m, entering);
        let facet = facets.refraction;
        match refract(d, facet, n1 / n2) {
            Some(dir) => {
                let r = schlick(-d.dot(facet), -dir.dot(facet), n1, n2);
                Secondary {
                    refraction: Some((on_side(dir, n, false), Vec3::splat((1.0 - r) * m.t))),
                    reflection: Some((Branch::Reflection, m.specular * r, mirror(facets.reflection))),
                }
            }
            None => Secondary {
                refraction: None,
                reflection: Some((Branch::TotalInternalReflection, m.specular, mirror(facet))),
            },
        }
    }
}

impl Rules for AffRules {
    /// Blinn-Phong, as the original's `H = normalize(L - dir)`.
    #[inline(always)]
    fn highlight_cosine(ns: Vec3, l: Vec3, view: Vec3) -> f32 {
        SpdRules::highlight_cosine(ns, l, view)
    }

    /// Clamped to 1 in each channel: the original clamps every ray's colour.
    #[inline(always)]
    fn returned(color: Vec3) -> Vec3 {
        color.min(Vec3::ONE)
    }

    /// `fm`'s ambient colour.
    #[inline(always)]
    fn ambient_reflectance(m: &Material, _diffuse: Vec3) -> Vec3 {
        m.ambient
    }

    /// About the shading normal.
    #[inline(always)]
    fn smooth_facets(_n: Vec3, ns: Vec3) -> Facets {
        Facets::smooth(ns)
    }

    /// About `facets` (the shading normal), each ray folded back to its side of the
    /// surface `n` where the interpolated normal would send it across.
    #[inline(always)]
    fn secondary(m: &Material, d: Vec3, n: Vec3, entering: bool, facets: &Facets) -> Secondary {
        // The original's `col1 * mat.specular * (1 - mat.T)`; it traces the mirror
        // ray again for the transmitted share under total internal reflection.
        let mirror = m.specular * (m.ks * (1.0 - m.t));
        let mut split = whitted_split(m, d, facets.reflection, entering, mirror);
        split.reflection = split
            .reflection
            .filter(|r| r.1 != Vec3::ZERO)
            .map(|(kind, w, dir)| (kind, w, on_side(dir, n, true)));
        split.refraction = split.refraction.map(|(dir, w)| (on_side(dir, n, false), w));
        split
    }
}

impl Model {
    /// The secondary rays of a hit on a smooth surface under this model's rules (see
    /// [`Rules`]).
    pub fn secondary(self, m: &Material, d: Vec3, n: Vec3, entering: bool) -> Secondary {
        let facets = Facets::smooth(n);
        match self {
            Model::Spd => SpdRules::secondary(m, d, n, entering, &facets),
            Model::P3f => P3fRules::secondary(m, d, n, entering, &facets),
            Model::Aff => AffRules::secondary(m, d, n, entering, &facets),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn p3f_glass_splits_by_fresnel_and_absorbs_inside() {
        let glass = Material {
            color: Vec3::new(1.0, 0.5, 0.25),
            kd: 0.0,
            specular: Vec3::ONE,
            ks: 0.2,
            shine: 20.0,
            t: 1.0,
            ior: 1.5,
            ..Material::DEFAULT
        };
        let n = Vec3::new(0.0, 1.0, 0.0);
        let s = Model::P3f.secondary(&glass, -n, n, true);
        let (dir, tw) = s.refraction.unwrap();
        assert!(close(dir, -n));
        // (1 - R) T, R = 0.04 at normal incidence: the colour absorbs inside instead.
        assert!(close(tw, Vec3::splat(0.96)));
        assert_eq!(s.reflection.map(|(k, ..)| k), Some(Branch::Reflection));
        assert!(close(s.reflection.unwrap().1, Vec3::splat(0.04)));
        assert_eq!(P3fRules::absorption(&glass), Some(Vec3::new(0.0, 0.5, 0.75)));
        assert_eq!(
            P3fRules::absorption(&Material {
                color: Vec3::ONE,
                ..glass
            }),
            None
        );
        // Leaving past the critical angle: everything goes to the mirror ray.
        let d = Vec3::new(0.8, -0.6, 0.0);
        let s = Model::P3f.secondary(&glass, d, n, false);
        assert_eq!(s.refraction, None);
        assert_eq!(
            s.reflection,
            Some((Branch::TotalInternalReflection, Vec3::ONE, reflect(d, n)))
        );
        // Opaque P3F: a mirror ray of Ks times the specular colour, only if Ks > 0.
        let metal = Material {
            t: 0.0,
            specular: Vec3::new(1.0, 0.5, 0.0),
            ks: 0.5,
            ..glass
        };
        let s = Model::P3f.secondary(&metal, -n, n, true);
        assert_eq!(
            s.reflection,
            Some((Branch::Reflection, Vec3::new(0.5, 0.25, 0.0), n))
        );
        let matte = Material { ks: 0.0, ..metal };
        assert_eq!(Model::P3f.secondary(&matte, -n, n, true).reflection, None);
    }

    #[test]
    fn aff_mirrors_by_the_specular_colour_times_one_minus_t() {
        let glass = Material {
            specular: Vec3::new(1.0, 0.5, 0.0),
            ks: 0.4,
            t: 0.5,
            ior: 1.5,
            ..Material::DEFAULT
        };
        let n = Vec3::new(0.0, 1.0, 0.0);
        let s = Model::Aff.secondary(&glass, -n, n, true);
        // Ks S (1 - T) = (0.4, 0.2, 0) * 0.5; the refracted ray goes straight on at T.
        assert_eq!(
            s.reflection,
            Some((Branch::Reflection, Vec3::new(0.2, 0.1, 0.0), n))
        );
        assert_eq!(s.refraction, Some((-n, Vec3::splat(0.5))));
        // Leaving past the critical angle: the mirror ray carries T besides.
        let d = Vec3::new(0.8, -0.6, 0.0);
        let s = Model::Aff.secondary(&glass, d, n, false);
        assert_eq!(s.refraction, None);
        let (kind, weight, _) = s.reflection.unwrap();
        assert_eq!(
            (kind, weight),
            (Branch::TotalInternalReflection, Vec3::new(0.7, 0.6, 0.5))
        );
        // No specular colour, opaque: no mirror ray; the ambient colour is `fm`'s.
        let matte = Material {
            ks: 0.0,
            t: 0.0,
            ambient: Vec3::splat(0.3),
            ..glass
        };
        assert_eq!(Model::Aff.secondary(&matte, -n, n, true).reflection, None);
        assert_eq!(AffRules::ambient_reflectance(&matte, Vec3::ONE), Vec3::splat(0.3));
        // Smooth mirrors reflect about the interpolated normal (0.6, 0.8, 0), not the
        // flat facet's (0, 1, 0): straight down, -y, comes back along
        // d - 2 (d.ns) ns = (0.96, 0.28, 0).
        let mirror = Material { t: 0.0, ..glass };
        let ns = Vec3::new(0.6, 0.8, 0.0);
        let facets = AffRules::smooth_facets(n, ns);
        let (_, _, dir) = AffRules::secondary(&mirror, -n, n, true, &facets)
            .reflection
            .unwrap();
        assert!(close(dir, Vec3::new(0.96, 0.28, 0.0)), "{dir:?}");
    }
}
