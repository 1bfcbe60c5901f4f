//! The probe's path loop over W lanes.

use super::*;

/// What a probe variant does in lanes beyond the path arithmetic.
#[derive(Clone, Copy)]
pub(crate) struct Variant {
    /// Random numbers, hit points, material and light data gathered in lane loops (else per
    /// lane, through `Sampler` and the scene's own types).
    pub(crate) gather: bool,
    /// Closest hits by the packet traversal (else one ray at a time through quasar's BVH).
    pub(crate) packet: bool,
    /// Shadow rays by the packet traversal.
    pub(crate) shadow_packet: bool,
    /// The light sample and the BSDF sample written for lanes, branch-free, for Lambertian
    /// surfaces and area lights only (else quasar's own `DiffuseBsdf` and `DielectricBsdf`
    /// called in the lane loops).
    pub(crate) diffuse_lanes: bool,
}

/// Lane `i`'s throughput times the scattering `weight`, then `pt`'s Russian roulette
/// ([`russian_roulette`], from `PtSettings`' `rr_depth` scattering events on, with the `depth`
/// events before this one): false when the path ends there (a non-finite throughput or the
/// roulette), as `pt::trace` ends it.
#[inline(always)]
fn scatter_and_roulette<const W: usize>(
    beta: &mut [L<W>; NW],
    i: usize,
    weight: SampledSpectrum,
    eta_scale: f32,
    depth: u32,
    u: f32,
) -> bool {
    let mut b = SampledSpectrum(std::array::from_fn(|k| beta[k][i] * weight.0[k]));
    let go = b.is_finite() && (depth + 1 < PtSettings::default().rr_depth || russian_roulette(&mut b, eta_scale, u));
    for k in 0..NW {
        beta[k][i] = b.0[k];
    }
    go
}

/// The side of a surface a path arrives on, from wo . ng (`wo_n`), as the sign of the local z
/// of the directions that leave it there: 1 in front, -1 behind a two-sided surface, 0 behind
/// a one-sided one (nothing scatters).
#[inline(always)]
fn arrival_side(wo_n: f32, two_sided: bool) -> f32 {
    if wo_n > 0.0 {
        1.0
    } else if wo_n < 0.0 && two_sided {
        -1.0
    } else {
        0.0
    }
}

/// Sum of luminance over the image, from the probe at width W; `stages`, when given, receives
/// the seconds spent in each part of the loop (the clock read costs time of its own).
pub(crate) fn render_lanes<const W: usize>(
    scene: &Scene,
    probe: &Probe,
    camera: &Camera,
    spp: u32,
    seed: u64,
    v: Variant,
    mut stages: Option<&mut [f64; N_STAGES]>,
) -> f64 {
    let (tab, bvh, tris) = (&probe.tables, &probe.bvh, &probe.tris);
    let mode = TransportMode::Radiance;
    let rr_depth = PtSettings::default().rr_depth;
    let (w, h) = (camera.width() as u64, camera.height() as u64);
    let jobs = w * h * spp as u64;
    let mut next = 0u64;
    let mut sum_y = 0.0f64;
    let mut rng = LaneRng::<W> { state: [0; W], inc: [1; W] };
    let mut samplers: Vec<Sampler> = (0..W).map(|_| Sampler::new(0, 0, 0)).collect();
    let mut wls: Vec<SampledWavelengths> = (0..W).map(|_| SampledWavelengths::sample_visible(0.5)).collect();
    // the paths
    let mut busy = [false; W];
    let mut ending = [false; W];
    let mut lambda = [[500.0f32; W]; NW];
    let (mut o, mut d) = (V::<W>::ZERO, V::<W>::ZERO);
    let mut beta = [[0.0f32; W]; NW];
    let mut rad = [[0.0f32; W]; NW];
    let mut prev_p = V::<W>::ZERO;
    let mut prev_pdf = [0.0f32; W];
    let mut eta_scale = [1.0f32; W];
    let mut depth = [0u32; W];
    let mut pending = [false; W];
    let (mut shadow_o, mut shadow_d) = (V::<W>::ZERO, V::<W>::ZERO);
    let mut shadow_t = [0.0f32; W];
    let mut pc = [[0.0f32; W]; NW];
    // this round's hits
    let mut hit = [false; W];
    let mut escaped = [false; W];
    let mut prim = [0u32; W];
    let (mut b1, mut b2) = ([0.0f32; W], [0.0f32; W]);
    let (mut p, mut pe, mut ng) = (V::<W>::ZERO, V::<W>::ZERO, V::<W>::ZERO);
    let mut mat = [0u32; W];
    let mut light = [NONE; W];
    let mut nee = [false; W];
    let mut le = [[0.0f32; W]; NW];
    let mut r = [[0.0f32; W]; NW];
    let mut u_light = [0u64; W];
    let mut li = [0u32; W];
    let mut lsel = [0.0f32; W];
    let mut lle = [[0.0f32; W]; NW];
    let mut u_l = [[0.0f32; W]; 2];
    let mut u_c = [0.0f32; W];
    let mut u_b = [[0.0f32; W]; 2];
    let mut u_rr = [1.0f32; W];
    let mut wi = V::<W>::ZERO;
    let (mut lv, mut le1, mut le2, mut lnrm) = (V::<W>::ZERO, V::<W>::ZERO, V::<W>::ZERO, V::<W>::ZERO);
    let (mut larea, mut harea, mut hsel) = ([0.0f32; W], [0.0f32; W], [0.0f32; W]);
    let (mut ltwo, mut htwo, mut mtwo) = ([false; W], [false; W], [false; W]);
    let mut clock = stages.as_ref().map(|_| Instant::now());
    let mut lap = |k: usize, clock: &mut Option<Instant>| {
        if let (Some(s), Some(c)) = (stages.as_deref_mut(), clock.as_mut()) {
            let n = Instant::now();
            s[k] += (n - *c).as_secs_f64();
            *c = n;
        }
    };
    let (env_row, env_sel) = tab.env.unwrap_or((0, 0.0));
    let env = tab.env.is_some();
    loop {
        // 1. pending shadow rays, then paths that ended: film; free lanes: the next samples
        let blocked = if v.shadow_packet {
            bvh.occluded(&shadow_o, &shadow_d, &shadow_t, &pending)
        } else {
            let mut b = [false; W];
            for i in 0..W {
                if pending[i] {
                    let mut ray = Ray::new(shadow_o.get(i), shadow_d.get(i));
                    ray.t_max = shadow_t[i];
                    b[i] = scene.occluded(&ray);
                }
            }
            b
        };
        lap(0, &mut clock);
        for i in 0..W {
            if pending[i] && !blocked[i] {
                for k in 0..NW {
                    rad[k][i] += pc[k][i];
                }
            }
            pending[i] = false;
            if ending[i] {
                ending[i] = false;
                busy[i] = false;
                let l = SampledSpectrum(std::array::from_fn(|k| rad[k][i]));
                let y = wls[i].xyz_weights().apply_vec(l).y;
                if y.is_finite() {
                    sum_y += y as f64;
                }
            }
            if !busy[i] && next < jobs {
                let (pixel, s) = (next / spp as u64, next % spp as u64);
                next += 1;
                let (u_wl, jitter) = if v.gather {
                    rng.start(i, seed, pixel, s);
                    let u = unit(rng.next_one(i));
                    (u, Vec2::new(unit(rng.next_one(i)), unit(rng.next_one(i))))
                } else {
                    samplers[i] = Sampler::new(seed, pixel, s);
                    (samplers[i].get_1d(), samplers[i].get_2d())
                };
                let wl = SampledWavelengths::sample_visible(u_wl);
                let ray = camera.ray(Vec2::new((pixel % w) as f32, (pixel / w) as f32) + jitter);
                busy[i] = true;
                for k in 0..NW {
                    lambda[k][i] = wl.lambda(k);
                    beta[k][i] = 1.0;
                    rad[k][i] = 0.0;
                }
                wls[i] = wl;
                o.set(i, ray.origin);
                d.set(i, ray.dir);
                prev_p.set(i, ray.origin);
                prev_pdf[i] = f32::INFINITY;
                eta_scale[i] = 1.0;
                depth[i] = 0;
            }
        }
        if !busy.iter().any(|&b| b) {
            break;
        }
        lap(1, &mut clock);
        // 2. closest hits
        if v.packet {
            (prim, _, b1, b2) = bvh.nearest(&o, &d, &busy);
        } else {
            for i in 0..W {
                prim[i] = NONE;
                if busy[i]
                    && let Some(hh) = scene.accel.intersect(&Ray::new(o.get(i), d.get(i)))
                {
                    (prim[i], b1[i], b2[i]) = (hh.prim, hh.b1, hh.b2);
                }
            }
        }
        for i in 0..W {
            hit[i] = busy[i] && prim[i] != NONE;
            escaped[i] = busy[i] && prim[i] == NONE;
        }
        lap(2, &mut clock);
        // 3. what the lanes gather: hit point, material, emission, random numbers, the light
        //    sample's light (next-event estimation at the vertices that are not specular)
        let mut idx = [0usize; W];
        for i in 0..W {
            idx[i] = if hit[i] { prim[i] as usize } else { 0 };
        }
        if v.gather {
            for i in 0..W {
                let j = idx[i];
                let v0 = Vec3::new(tris.v0[0][j], tris.v0[1][j], tris.v0[2][j]);
                let a = Vec3::new(tris.e1[0][j], tris.e1[1][j], tris.e1[2][j]) * b1[i];
                let b = Vec3::new(tris.e2[0][j], tris.e2[1][j], tris.e2[2][j]) * b2[i];
                p.set(i, v0 + a + b);
                pe.set(i, point_error(v0, a, b));
                (ng.x[i], ng.y[i], ng.z[i]) = (tris.n[0][j], tris.n[1][j], tris.n[2][j]);
                mat[i] = tris.material[j];
                light[i] = if hit[i] { tris.light[j] } else { NONE };
            }
        } else {
            for i in 0..W {
                let g = &scene.accel.geom[idx[i]];
                let (pp, pp_err) = g.point_with_error(b1[i], b2[i]);
                p.set(i, pp);
                pe.set(i, pp_err);
                ng.set(i, Vec3::from(g.n));
                mat[i] = scene.accel.info[idx[i]].material;
                light[i] = if hit[i] { scene.accel.info[idx[i]].light } else { NONE };
            }
        }
        for i in 0..W {
            let m = mat[i] as usize;
            let specular = tab.dielectric[m] && (tab.eta[m] == 1.0 || tab.alpha[m] < SMOOTH_ALPHA);
            nee[i] = hit[i] && !specular;
        }
        if v.gather {
            for k in 0..NW {
                r[k] = lookup_lanes(&tab.refl_flat, &mat, &lambda[k]);
            }
            let hi = rng.next(&nee);
            let lo = rng.next(&nee);
            for i in 0..W {
                u_light[i] = ((hi[i] as u64) << 32) | lo[i] as u64;
            }
            u_l = [rng.uniform(&nee), rng.uniform(&nee)];
            u_c = rng.uniform(&hit);
            u_b = [rng.uniform(&hit), rng.uniform(&hit)];
            let mut late = [false; W];
            for i in 0..W {
                late[i] = hit[i] && depth[i] + 1 >= rr_depth;
            }
            let u = rng.uniform(&late);
            for i in 0..W {
                u_rr[i] = if late[i] { u[i] } else { 1.0 };
            }
        } else {
            for i in 0..W {
                for k in 0..NW {
                    r[k][i] = lookup(&tab.refl_flat, mat[i], lambda[k][i]);
                }
                if !hit[i] {
                    continue;
                }
                let sampler = &mut samplers[i];
                if nee[i] {
                    u_light[i] = sampler.get_u64();
                    (u_l[0][i], u_l[1][i]) = sampler.get_2d().into();
                }
                u_c[i] = sampler.get_1d();
                (u_b[0][i], u_b[1][i]) = sampler.get_2d().into();
                u_rr[i] = if depth[i] + 1 >= rr_depth { sampler.get_1d() } else { 1.0 };
            }
        }
        // the light choice (Walker's alias table), per lane
        for i in 0..W {
            let (l, sel) = if nee[i] { scene.light_sampler.sample(u_light[i]).unwrap_or((0, 0.0)) } else { (0, 0.0) };
            (li[i], lsel[i]) = (l as u32, sel);
        }
        // the emission at the hit (or of the environment, for an escaped ray) and of the chosen
        // light
        let mut emit_row = [0u32; W];
        let mut lemit_row = [0u32; W];
        for i in 0..W {
            let hl = if light[i] != NONE { light[i] as usize } else { 0 };
            emit_row[i] = if escaped[i] { env_row } else { tab.light_emission[hl] };
            lemit_row[i] = tab.light_emission[li[i] as usize];
        }
        if v.gather {
            for k in 0..NW {
                le[k] = lookup_lanes(&tab.emit_flat, &emit_row, &lambda[k]);
                lle[k] = lookup_lanes(&tab.emit_flat, &lemit_row, &lambda[k]);
            }
        } else {
            for i in 0..W {
                for k in 0..NW {
                    le[k][i] = lookup(&tab.emit_flat, emit_row[i], lambda[k][i]);
                    lle[k][i] = lookup(&tab.emit_flat, lemit_row[i], lambda[k][i]);
                }
            }
        }
        for i in 0..W {
            let l = li[i] as usize;
            lv.set(i, tab.light_v0[l]);
            le1.set(i, tab.light_e1[l]);
            le2.set(i, tab.light_e2[l]);
            lnrm.set(i, tab.light_n[l]);
            larea[i] = tab.light_area[l];
            ltwo[i] = tab.emit_two_sided[lemit_row[i] as usize];
            let hl = if light[i] != NONE { light[i] as usize } else { 0 };
            (harea[i], hsel[i]) = (tab.light_area[hl], tab.light_sel[hl]);
            htwo[i] = tab.emit_two_sided[emit_row[i] as usize];
            mtwo[i] = tab.two_sided[mat[i] as usize];
        }
        lap(3, &mut clock);
        // 4. what the ray found: the environment (escaped), or an emitter's radiance at the hit,
        //    weighted against the light sample that could have found it
        for i in 0..W {
            let wo_n = -(d.x[i] * ng.x[i] + d.y[i] * ng.y[i] + d.z[i] * ng.z[i]);
            let lit = hit[i] && light[i] != NONE && (htwo[i] || wo_n > 0.0);
            // pdf_li_area(prev.p, si.p, si.ng)
            let (dx, dy, dz) = (p.x[i] - prev_p.x[i], p.y[i] - prev_p.y[i], p.z[i] - prev_p.z[i]);
            let dist2 = dx * dx + dy * dy + dz * dz;
            let cos_l = (ng.x[i] * dx + ng.y[i] * dy + ng.z[i] * dz).abs() / dist2.sqrt();
            let pdf = dist2 / (cos_l * harea[i]);
            let p_area = hsel[i] * if pdf.is_finite() { pdf } else { 0.0 };
            let p_light = if escaped[i] { env_sel * UNIFORM_SPHERE_PDF } else { p_area };
            let mis = power(prev_pdf[i], p_light);
            let m = if lit || (escaped[i] && env) { mis } else { 0.0 };
            for k in 0..NW {
                rad[k][i] += beta[k][i] * (le[k][i] * m);
            }
            ending[i] = escaped[i];
        }
        if v.diffuse_lanes {
            // 5'. the light sample on the chosen triangle, the Lambertian BSDF and its density,
            //     the power heuristic, the shadow ray
            for i in 0..W {
                let su = u_l[0][i].sqrt();
                let (c1, c2) = (1.0 - su, u_l[1][i] * su);
                let dx = lv.x[i] + le1.x[i] * c1 + le2.x[i] * c2 - p.x[i];
                let dy = lv.y[i] + le1.y[i] * c1 + le2.y[i] * c2 - p.y[i];
                let dz = lv.z[i] + le1.z[i] * c1 + le2.z[i] * c2 - p.z[i];
                let dist2 = dx * dx + dy * dy + dz * dz;
                let dist = dist2.sqrt();
                let (wx, wy, wz) = (dx / dist, dy / dist, dz / dist);
                let cos_l_signed = -(lnrm.x[i] * wx + lnrm.y[i] * wy + lnrm.z[i] * wz);
                let cos_l = cos_l_signed.abs();
                let pdf = dist2 / (cos_l * larea[i]);
                let p_light = lsel[i] * pdf;
                let wo_n = -(d.x[i] * ng.x[i] + d.y[i] * ng.y[i] + d.z[i] * ng.z[i]);
                let side = arrival_side(wo_n, mtwo[i]);
                let cos_i = ng.x[i] * wx + ng.y[i] * wy + ng.z[i] * wz;
                let p_bsdf = cos_i.abs() * FRAC_1_PI;
                let black = (0..NW).all(|k| r[k][i] == 0.0);
                let ok = nee[i]
                    && !black
                    && side * cos_i > 0.0
                    && (ltwo[i] || cos_l_signed > 0.0)
                    && cos_l > 0.0
                    && dist2 > 0.0
                    && pdf.is_finite()
                    && lsel[i] > 0.0;
                let c = if ok { cos_i.abs() * power(p_light, p_bsdf) / p_light } else { 0.0 };
                for k in 0..NW {
                    pc[k][i] = beta[k][i] * (r[k][i] * FRAC_1_PI * lle[k][i] * c);
                }
                pending[i] = ok;
                (shadow_d.x[i], shadow_d.y[i], shadow_d.z[i]) = (wx, wy, wz);
                shadow_t[i] = (dist * (1.0 - 1e-4)).max(0.0);
            }
            offset(&p, &pe, &ng, &shadow_d, &mut shadow_o);
            // 6'. the cosine-weighted BSDF sample, the throughput, Russian roulette
            for i in 0..W {
                let wo_n = -(d.x[i] * ng.x[i] + d.y[i] * ng.y[i] + d.z[i] * ng.z[i]);
                let side = arrival_side(wo_n, mtwo[i]);
                let mut local = cosine_hemisphere(Vec2::new(u_b[0][i], u_b[1][i]));
                local.z *= side;
                let n = ng.get(i);
                let dir = Frame::from_z(n).from_local(local);
                let pdf = local.z.abs() * FRAC_1_PI;
                let black = (0..NW).all(|k| r[k][i] == 0.0);
                let consistent = (local.z * wo_n > 0.0) == (dir.dot(n) * wo_n > 0.0);
                let alive = side != 0.0 && !black && pdf > 0.0 && consistent;
                let weight = SampledSpectrum(std::array::from_fn(|k| r[k][i]));
                let go = scatter_and_roulette(&mut beta, i, weight, eta_scale[i], depth[i], u_rr[i]);
                wi.set(i, dir);
                prev_pdf[i] = pdf;
                ending[i] = ending[i] || (hit[i] && !(alive && go));
                depth[i] += 1;
            }
        } else {
            // 5. the light sample: a point on the chosen triangle or a direction of the environment,
            //    its density in solid angle, the BSDF and its density, the power heuristic, the
            //    shadow ray
            for i in 0..W {
                let l = li[i] as usize;
                let n = ng.get(i);
                let frame = Frame::from_z(n);
                let wo_local = frame.to_local(-d.get(i));
                let pi = p.get(i);
                let (wl_dir, pdf, dist, lit) = if tab.light_env[l] {
                    (uniform_sphere(Vec2::new(u_l[0][i], u_l[1][i])), UNIFORM_SPHERE_PDF, f32::INFINITY, true)
                } else {
                    let (c1, c2) = uniform_triangle(Vec2::new(u_l[0][i], u_l[1][i]));
                    let pl = tab.light_v0[l] + tab.light_e1[l] * c1 + tab.light_e2[l] * c2;
                    let dd = pl - pi;
                    let dist2 = dd.length_squared();
                    let dist = dist2.sqrt();
                    let dir = dd / dist;
                    let cos_l = tab.light_n[l].dot(-dir).abs();
                    let lit = (tab.emit_two_sided[lemit_row[i] as usize] || tab.light_n[l].dot(-dir) > 0.0)
                        && dist2 > 0.0
                        && cos_l > 0.0;
                    (dir, dist2 / (cos_l * tab.light_area[l]), dist, lit)
                };
                let wi_local = frame.to_local(wl_dir);
                let m = mat[i] as usize;
                let (f, p_bsdf) = if tab.dielectric[m] {
                    DielectricBsdf::new(tab.eta[m], TrowbridgeReitz::new(tab.alpha[m]).with_masking(scene.masking))
                        .f_pdf(wo_local, wi_local, mode)
                } else {
                    DiffuseBsdf::new(SampledSpectrum(std::array::from_fn(|k| r[k][i])), tab.two_sided[m])
                        .f_pdf(wo_local, wi_local)
                };
                let f = f * wi_local.z.abs();
                let p_light = lsel[i] * pdf;
                let ok = nee[i] && lit && pdf > 0.0 && pdf.is_finite() && lsel[i] > 0.0;
                let c = if ok { power_heuristic(p_light, p_bsdf) / p_light } else { 0.0 };
                for k in 0..NW {
                    pc[k][i] = beta[k][i] * (f.0[k] * lle[k][i] * c);
                }
                pending[i] = ok && !f.is_black();
                shadow_d.set(i, wl_dir);
                shadow_t[i] = if dist.is_finite() { (dist * (1.0 - 1e-4)).max(0.0) } else { f32::INFINITY };
            }
            offset(&p, &pe, &ng, &shadow_d, &mut shadow_o);
            // 6. the BSDF sample in the frame of the normal, the throughput, Russian roulette
            for i in 0..W {
                let n = ng.get(i);
                let frame = Frame::from_z(n);
                let wo = -d.get(i);
                let wo_local = frame.to_local(wo);
                let m = mat[i] as usize;
                let u = Vec2::new(u_b[0][i], u_b[1][i]);
                let bs = if tab.dielectric[m] {
                    DielectricBsdf::new(tab.eta[m], TrowbridgeReitz::new(tab.alpha[m]).with_masking(scene.masking))
                        .sample_f(wo_local, u_c[i], u, mode)
                } else {
                    DiffuseBsdf::new(SampledSpectrum(std::array::from_fn(|k| r[k][i])), tab.two_sided[m])
                        .sample_f(wo_local, u, mode)
                };
                let (mut alive, mut weight, mut dir, mut pdf) = (false, SampledSpectrum::zero(), Vec3::Z, 0.0);
                if let Some(bs) = bs
                    && bs.pdf > 0.0
                    && !bs.f.is_black()
                {
                    let w_world = frame.from_local(bs.wi);
                    alive = (bs.wi.z * wo_local.z > 0.0) == (w_world.dot(n) * wo.dot(n) > 0.0);
                    weight = bs.f * (bs.wi.z.abs() / bs.pdf);
                    dir = w_world;
                    pdf = if bs.specular { f32::INFINITY } else { bs.pdf };
                    if bs.lobe == Lobe::Transmission {
                        eta_scale[i] *= bs.eta * bs.eta;
                    }
                }
                let go = scatter_and_roulette(&mut beta, i, weight, eta_scale[i], depth[i], u_rr[i]);
                wi.set(i, dir);
                prev_pdf[i] = pdf;
                ending[i] = ending[i] || (hit[i] && !(alive && go));
                depth[i] += 1;
            }
        }
        prev_p = p;
        d = wi;
        offset(&p, &pe, &ng, &d, &mut o);
        lap(4, &mut clock);
    }
    sum_y
}
