//! Generators: grids of copies of a body template.

use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

use crate::check::{Check, Checker};
use crate::{Body, GeneratorFile, MAX_BODIES, Shape};

impl Checker<'_> {
    /// The bodies of generator `gi`, appended to `out` (`first_index`: the
    /// scene index of `out`'s first body); returns whether the template's
    /// `restitution` was written.
    pub(crate) fn generator(
        &self,
        gi: usize,
        g: &GeneratorFile,
        first_index: usize,
        out: &mut Vec<Body>,
    ) -> Check<bool> {
        let at = format!("generators[{gi}]");
        let f = |k: &str| format!("{at}.{k}");
        let origin = self.vector(
            &f("origin"),
            g.origin
                .as_deref()
                .ok_or(())
                .or_else(|_| self.err(&f("origin"), "missing"))?,
        )?;
        let spacing = self.vector(
            &f("spacing"),
            g.spacing
                .as_deref()
                .ok_or(())
                .or_else(|_| self.err(&f("spacing"), "missing"))?,
        )?;
        let count = match &g.count {
            Some(c) if c.len() == self.dim => c.clone(),
            Some(c) => {
                return self.err(
                    &f("count"),
                    format!(
                        "must have {} components (dim = {}), got {}",
                        self.dim,
                        self.dim,
                        c.len()
                    ),
                );
            }
            None => return self.err(&f("count"), "missing"),
        };
        let total = count
            .iter()
            .try_fold(1u64, |a, c| a.checked_mul(*c))
            .unwrap_or(u64::MAX);
        if count.contains(&0) {
            return self.err(&f("count"), "every count must be >= 1");
        }
        if total > MAX_BODIES as u64 {
            return self.err(&f("count"), format!("{total} bodies: at most {MAX_BODIES}"));
        }
        let Some(template) = &g.body else {
            return self.err(&f("body"), "missing: the template of the generated bodies");
        };
        let (base, restitution_written) = self.body(&f("body"), &f("body"), template, true)?;
        let masses = match &g.masses {
            Some(ms) if ms.is_empty() => return self.err(&f("masses"), "must not be empty"),
            Some(ms) => {
                for (i, m) in ms.iter().enumerate() {
                    self.positive(&format!("{}[{i}]", f("masses")), *m)?;
                }
                if base.fixed {
                    return self.err(
                        &f("masses"),
                        "the template is fixed: fixed bodies have no mass",
                    );
                }
                ms.clone()
            }
            None => {
                if !base.fixed && base.mass.is_none() {
                    return self.err(
                        &f("body.mass"),
                        "missing: give the template a mass or the generator `masses`",
                    );
                }
                Vec::new()
            }
        };
        let radii = match &g.radii {
            Some(rs) if rs.is_empty() => return self.err(&f("radii"), "must not be empty"),
            Some(rs) => {
                if !matches!(base.shape, Shape::Ball { .. }) {
                    return self.err(&f("radii"), "only for a ball template");
                }
                for (i, r) in rs.iter().enumerate() {
                    self.positive(&format!("{}[{i}]", f("radii")), *r)?;
                }
                rs.clone()
            }
            None => Vec::new(),
        };
        let materials = match &g.materials {
            Some(ms) if ms.is_empty() => return self.err(&f("materials"), "must not be empty"),
            Some(_) if !base.fixed && !base.law => {
                return self.err(
                    &f("materials"),
                    "the template does not follow the law (`law: false`): its bodies have no material",
                );
            }
            Some(ms) => {
                let mut out = Vec::with_capacity(ms.len());
                for (i, m) in ms.iter().enumerate() {
                    out.push(self.material(&format!("{}[{i}]", f("materials")), m)?);
                }
                out
            }
            None => Vec::new(),
        };
        let speed = self.non_negative(&f("speed"), g.speed.unwrap_or(0.0))?;
        if speed > 0.0 && base.fixed {
            return self.err(
                &f("speed"),
                "the template is fixed: fixed bodies cannot move",
            );
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(g.seed.unwrap_or(1));
        let mut index = vec![0u64; self.dim];
        for n in 0..total as usize {
            let mut b = base.clone();
            b.origin = format!("{at}[{n}] (bodies[{}])", first_index + out.len());
            for k in 0..self.dim {
                b.position[k] = origin[k] + spacing[k] * index[k] as f64;
            }
            if !masses.is_empty() {
                b.mass = Some(masses[n % masses.len()]);
            }
            if !radii.is_empty() {
                b.shape = Shape::Ball {
                    radius: radii[n % radii.len()],
                };
            }
            if !materials.is_empty() {
                b.material = Some(materials[n % materials.len()]);
            }
            if speed > 0.0 {
                let dir = direction(&mut rng, self.dim);
                for (v, d) in b.velocity.iter_mut().zip(&dir) {
                    *v += speed * d;
                }
            }
            // Finite inputs can still overflow here (found by fuzzing): a
            // generated body's vectors must be finite like written ones.
            if let Some(k) = b.position.iter().position(|x| !x.is_finite()) {
                return self.err(
                    &f("spacing"),
                    format!(
                        "{} would be at position[{k}] = {}: origin + spacing x index overflows",
                        b.origin, b.position[k]
                    ),
                );
            }
            if let Some(k) = b.velocity.iter().position(|x| !x.is_finite()) {
                return self.err(
                    &f("speed"),
                    format!(
                        "{} would move at velocity[{k}] = {}: the template's velocity + speed overflows",
                        b.origin, b.velocity[k]
                    ),
                );
            }
            out.push(b);
            for k in 0..self.dim {
                index[k] += 1;
                if index[k] < count[k] {
                    break;
                }
                index[k] = 0;
            }
        }
        Ok(restitution_written)
    }
}

/// A uniformly random unit vector of `dim` components (rejection sampling
/// in the cube), for the generators' random directions: the scene's seeded
/// generator gives the same scene on every machine.
fn direction(rng: &mut Xoshiro256PlusPlus, dim: usize) -> Vec<f64> {
    loop {
        let v: Vec<f64> = (0..dim).map(|_| rng.random_range(-1.0..1.0)).collect();
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 1e-3 && n <= 1.0 {
            return v.into_iter().map(|x| x / n).collect();
        }
    }
}
