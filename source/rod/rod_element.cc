#include <suturesim/rod/rod_element.h>

#include <stdexcept>

namespace suturesim::rod
{
  namespace
  {
    /// Midpoint quaternion q_m, half-relative quaternion q_h = q_m* q₂ (so that
    /// R₁ = R_m exp(−h), R₂ = R_m exp(h), ψ = 2h) and the rotation vector ψ.
    struct Kinematics
    {
      Quat qm, qh;
      Vec3 U;   ///< vector part of q₁* q₂ = q_h q_h
      double s; ///< |U|²
      LogFactor f;
      Vec3 psi;
    };

    Kinematics
    kinematics(const Quat &q1, const Quat &q2_in)
    {
      // q and −q are one rotation; take the representative in q₁'s hemisphere so that
      // (q₁ + q₂)/|q₁ + q₂| is the geodesic midpoint
      const Quat q2 = q1.coeffs().dot(q2_in.coeffs()) < 0 ? Quat(-q2_in.coeffs()) : q2_in;
      Kinematics k;
      k.qm = Quat(q1.coeffs() + q2.coeffs()).normalized();
      k.qh = k.qm.conjugate() * q2;
      const Quat rel = q1.conjugate() * q2;
      if (rel.w() <= 1e-8)
        throw std::domain_error("relative rotation of an element's nodes reached pi");
      k.U   = rel.vec();
      k.s   = k.U.squaredNorm();
      k.f   = log_factor(k.s);
      k.psi = k.f.F * k.U;
      return k;
    }
  } // namespace

  ElementState
  element_state(const Vec3 &x1, const Quat &q1, const Vec3 &x2, const Quat &q2,
                const ElementReference &reference, const SectionStiffness &section)
  {
    const Kinematics k  = kinematics(q1, q2);
    const double     L0 = reference.length;
    ElementState     e;
    e.Rm     = k.qm.toRotationMatrix();
    e.Gamma  = e.Rm.transpose() * (x2 - x1) / L0 - reference.gamma0;
    e.K      = k.psi / L0 - reference.kappa0;
    e.N      = section.force.cwiseProduct(e.Gamma);
    e.M      = section.moment.cwiseProduct(e.K);
    e.energy = 0.5 * L0 * (e.Gamma.dot(e.N) + e.K.dot(e.M));
    return e;
  }

  ElementReference
  make_reference(const Vec3 &x1, const Quat &q1, const Vec3 &x2, const Quat &q2)
  {
    const Kinematics k = kinematics(q1, q2);
    ElementReference r;
    r.length = (x2 - x1).norm();
    r.gamma0 = k.qm.toRotationMatrix().transpose() * (x2 - x1) / r.length;
    r.kappa0 = k.psi / r.length;
    return r;
  }

  /*
   * Derivation of the tangent. Perturb the nodes by material rotations α_i = R_mᵀθ_i
   * and a material chord change e = R_mᵀ(Δx₂ − Δx₁); use σ = (α₁ + α₂)/2, w = α₂ − α₁
   * and z = (e, σ, w). With q_h = (c, u) and exp(α) = (1 − |α|²/8, α/2) + O(3):
   *
   * Midpoint. R_m' = R_m exp(χ) with exp(χ) ∝ exp(α₁)q_h* + exp(α₂)q_h = (s_w, s_v),
   *   s_w = 2c − w·u/2 + O(2),  s_v = cσ + (w×u)/2 − (σ·w)u/4 + O(3),
   * and χ = 2 s_v/s_w + O(3):
   *   χ₁ = σ − (û/2c) w,   χ₂ = −(σ·w)u/(4c) + (cσ + w×u/2)(w·u)/(4c²).
   * Chord. R_m'ᵀ(d + Δd) = g + y, g = R_mᵀd, y = e − χ×g − χ×e + ½χ×(χ×g) + O(3).
   * Relative rotation. q₁'*q₂' = q_h exp(−α₁)exp(α₂) q_h with exp(−α₁)exp(α₂) =
   * (1 − |w|²/8, w/2 − (σ×w)/4) + O(3); since q_h(0, y)q_h = (·, y − 2(y·u)u), its vector
   * part is p = U + p₁ + p₂ with
   *   p₁ = (I/2 − uuᵀ) w,   p₂ = −|w|²U/8 − (I − 2uuᵀ)(σ×w)/4,
   * and ψ' = F(|p|²)p, whose derivatives are
   *   Dψ[a] = F a + 2F'(U·a)U,
   *   D²ψ[a,b] = 2F'[(U·a)b + (U·b)a + (a·b)U] + 4F''(U·a)(U·b)U.
   * Energy. W' = W + N·y + M·δ + (yᵀC_N y + δᵀC_M δ)/(2L₀) with δ = ψ' − ψ. Collecting the
   * first-order terms gives the gradient, the second-order ones the quadratic form
   * zᵀAz whose symmetric part is half the Hessian.
   */
  ElementState
  element_tangent(const Vec3 &x1, const Quat &q1, const Vec3 &x2, const Quat &q2,
                  const ElementReference &reference, const SectionStiffness &section,
                  Vec12 &gradient, Mat12 *hessian_out)
  {
    const Kinematics k  = kinematics(q1, q2);
    const double     L0 = reference.length;
    ElementState     st;
    st.Rm     = k.qm.toRotationMatrix();
    const Vec3 g = st.Rm.transpose() * (x2 - x1);
    st.Gamma  = g / L0 - reference.gamma0;
    st.K      = k.psi / L0 - reference.kappa0;
    st.N      = section.force.cwiseProduct(st.Gamma);
    st.M      = section.moment.cwiseProduct(st.K);
    st.energy = 0.5 * L0 * (st.Gamma.dot(st.N) + st.K.dot(st.M));
    const Vec3 &N = st.N, &M = st.M, &U = k.U;

    const double c    = k.qh.w();
    const Vec3   u    = k.qh.vec();
    const Mat3   I    = Mat3::Identity();
    const Mat3   Cw   = skew(u) / (2 * c);            // χ₁ = σ − Cw w
    const Mat3   Pw   = 0.5 * I - u * u.transpose();  // p₁ = Pw w
    const Mat3   Jpsi = k.f.F * I + 2 * k.f.dF * U * U.transpose();
    const Mat3   Dw   = Jpsi * Pw;                    // δ₁ = Dw w
    const Mat3   G    = skew(g);
    const Mat3   GCw  = G * Cw;
    // first order: y₁ = e + Gσ − GCw w, δ₁ = Dw w, χ₁ = σ − Cw w
    const Vec3 ge = N, gs = G.transpose() * N, gw = -GCw.transpose() * N + Dw.transpose() * M;
    const Mat3 &R = st.Rm;
    {
      const Vec3 Ge = R * ge, Gs = R * gs, Gw = R * gw;
      gradient << -Ge, 0.5 * Gs - Gw, Ge, 0.5 * Gs + Gw;
    }
    if (!hessian_out)
      return st;
    Mat12 &hessian = *hessian_out;

    // Hessian in z = (e, σ, w), built by 3×3 blocks; A holds the quadratic form, whose
    // symmetric part A + Aᵀ is the Hessian. Material part (already symmetric):
    const Vec3 cn = section.force / L0, cm = section.moment / L0;
    const Mat3 CnG = cn.asDiagonal() * G, CnGCw = cn.asDiagonal() * GCw;
    Mat3       Hee = cn.asDiagonal();
    Mat3       Hes = CnG, Hew = -CnGCw;
    Mat3       Hss = G.transpose() * CnG, Hsw = -G.transpose() * CnGCw;
    Mat3       Hww = GCw.transpose() * CnGCw + Dw.transpose() * cm.asDiagonal() * Dw;
    // geometric part: A_σe += N̂ and A_we += −Cwᵀ N̂ from −N·(χ₁×e) = χ₁ᵀ N̂ e
    const Mat3 Nh = skew(N);
    Hes += Nh.transpose();
    Hew += (-Cw.transpose() * Nh).transpose();
    // ½ N·(χ₁×(χ₁×g)) = χ₁ᵀ G2 χ₁ (G2 symmetric)
    const Mat3 G2  = 0.5 * (0.5 * (N * g.transpose() + g * N.transpose()) - N.dot(g) * I);
    const Mat3 G2C = G2 * Cw;
    Hss += 2 * G2;
    Hsw -= 2 * G2C;
    Hww += 2 * Cw.transpose() * G2C;
    // v·χ₂ (v = N×g) and M·Dψ[p₂] (m̃ = Jψ M): A_σw += X1, A_ww += X2
    const Vec3   v  = N.cross(g);
    const Vec3   mt = Jpsi * M;
    const Vec3   kv = mt - 2 * u.dot(mt) * u;
    const double MU = M.dot(U);
    const Mat3   X1 = (-v.dot(u) * I + v * u.transpose()) / (4 * c) + 0.25 * skew(kv);
    Mat3 X2 = u.cross(v) * u.transpose() / (8 * c * c) - (mt.dot(U) / 8) * I +
              Pw *
                (k.f.dF * (U * M.transpose() + M * U.transpose() + MU * I) +
                 2 * k.f.d2F * MU * U * U.transpose()) *
                Pw;
    Hsw += X1;
    Hww += X2 + X2.transpose();

    // back to (Δx₁, θ₁, Δx₂, θ₂): e = Rᵀ(Δx₂ − Δx₁), σ = Rᵀ(θ₁ + θ₂)/2, w = Rᵀ(θ₂ − θ₁)
    const Mat3  ee = R * Hee * R.transpose(), es = R * Hes * R.transpose(),
               ew = R * Hew * R.transpose(), ss = R * Hss * R.transpose(),
               sw = R * Hsw * R.transpose(), ww = R * Hww * R.transpose();
    const Mat3 xt1 = 0.5 * es - ew, xt2 = 0.5 * es + ew;
    const Mat3 t11 = 0.25 * ss - 0.5 * (sw + sw.transpose()) + ww;
    const Mat3 t12 = 0.25 * ss + 0.5 * (sw - sw.transpose()) - ww;
    const Mat3 t22 = 0.25 * ss + 0.5 * (sw + sw.transpose()) + ww;
    hessian.block<3, 3>(0, 0) = ee;
    hessian.block<3, 3>(0, 3) = -xt1;
    hessian.block<3, 3>(0, 6) = -ee;
    hessian.block<3, 3>(0, 9) = -xt2;
    hessian.block<3, 3>(3, 3) = t11;
    hessian.block<3, 3>(3, 6) = xt1.transpose();
    hessian.block<3, 3>(3, 9) = t12;
    hessian.block<3, 3>(6, 6) = ee;
    hessian.block<3, 3>(6, 9) = xt2;
    hessian.block<3, 3>(9, 9) = t22;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < a; ++b)
        hessian.block<3, 3>(3 * a, 3 * b) = hessian.block<3, 3>(3 * b, 3 * a).transpose();
    return st;
  }
} // namespace suturesim::rod
