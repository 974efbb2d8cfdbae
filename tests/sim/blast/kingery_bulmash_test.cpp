// Tests of sim/blast/kingery_bulmash and blast_point: the curves against a second transcription
// and an independent refit, physics consistency, joins, monotonicity, scaling, range handling.
#include "sim/blast/kingery_bulmash.hpp"

#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sim/blast/air.hpp"
#include "sim/blast/blast_point.hpp"

namespace brisance::blast {
namespace {

constexpr std::array kAllParameters = {
    KbParameter::incident_overpressure,  KbParameter::incident_impulse,
    KbParameter::arrival_time,           KbParameter::positive_duration,
    KbParameter::reflected_overpressure, KbParameter::reflected_impulse,
    KbParameter::shock_velocity};
constexpr std::array kCurves = {BurstCurve::spherical_free_air, BurstCurve::hemispherical_surface};

// Log-spaced scaled distances across [lo, hi].
std::vector<double> log_grid(double lo, double hi, int count) {
  std::vector<double> z;
  for (int i = 0; i < count; ++i)
    z.push_back(lo * std::pow(hi / lo, i / (count - 1.0)));
  return z;
}

double value(BurstCurve curve, KbParameter parameter, double z) {
  return kingery_bulmash_value(curve, parameter, z);
}

// --- Second transcription: the imperial Kingery–Bulmash set as ConWep carries it -------------
// (U = K0 + K1 log10(Z), Z in ft/lb^(1/3); psi, psi*ms/lb^(1/3), ms/lb^(1/3)), transcribed from
// the BlastLoading.C ConWep port of the AERO-S code, with its one typo (surface i_s piece 2,
// C2 = -0.0280816706301) replaced by -0.0260816706301, the value four other transcriptions and
// Swisdak's independent refit agree on. Compared through the exact unit conversions it checks
// every digit of our metric set except the higher coefficients both share.
struct ImperialPiece {
  BurstCurve curve;
  KbParameter parameter;
  double z_min_ft_lb13;
  double z_max_ft_lb13;
  double k0;
  double k1;
  std::vector<double> c;
};

const std::vector<ImperialPiece>& imperial_set() {
  // clang-format off
  static const std::vector<ImperialPiece> pieces = {
  // spherical free-air burst
  {BurstCurve::spherical_free_air, KbParameter::incident_overpressure, 0.134, 100, -0.756579301809, 1.35034249993, {1.77284970457, -1.69012801396, 0.00804973591951, 0.336743114941, -0.00516226351334, -0.0809228619888, -0.00478507266747, 0.00793030472242, 0.0007684469735}},
  {BurstCurve::spherical_free_air, KbParameter::incident_impulse, 0.134, 2.0, 1.04504877747, 3.24299066475, {1.43534136453, -0.443749377691, 0.168825414684, 0.0348138030308, -0.010435192824}},
  {BurstCurve::spherical_free_air, KbParameter::incident_impulse, 2.0, 100, -2.67912519532, 2.30629231803, {0.599008468099, -0.40463292088, -0.0142721946082, 0.00912366316617, -0.0006750681404, -0.00800863718901, 0.00314819515931, 0.00152044783382, -0.0007470265899}},
  {BurstCurve::spherical_free_air, KbParameter::arrival_time, 0.134, 100, -0.80501734056, 1.37407043777, {-0.0423733936826, 1.36456871214, -0.0570035692784, -0.182832224796, 0.0118851436014, 0.0432648687627, -0.0007997367834, -0.00436073555033}},
  {BurstCurve::spherical_free_air, KbParameter::positive_duration, 0.37, 2.239999905436229, 0.209440059933, 5.11588554305, {-0.801052722864, 0.164953518069, 0.127788499497, 0.00291430135946, 0.00187957449227, 0.0173413962543, 0.00269739758043, -0.00361976502798, -0.00100926577934}},
  {BurstCurve::spherical_free_air, KbParameter::positive_duration, 2.239999905436229, 5.749999408315388, -5.06778493835, 9.2996288611, {0.115874238335, -0.0297944268969, 0.0306329542941, 0.018340557407, -0.0173964666286, -0.00106321963576, 0.0056206003128, 0.0001618217499, -0.0006860188944}},
  {BurstCurve::spherical_free_air, KbParameter::positive_duration, 5.749999408315388, 100, -4.39590184126, 3.1524725264, {0.50659210403, 0.0967031995552, -0.00801302059667, 0.00482705779732, 0.00187587272287, -0.00246738509321, -0.000841116668, 0.0006193291052}},
  {BurstCurve::spherical_free_air, KbParameter::reflected_overpressure, 0.134, 100, -0.756579301809, 1.35034249993, {2.39106134946, -2.21400538997, 0.035119031446, 0.657599992109, 0.0141818951887, -0.243076636231, -0.0158699803158, 0.0492741184234, 0.00227639644004, -0.00397126276058}},
  {BurstCurve::spherical_free_air, KbParameter::reflected_impulse, 0.134, 100, -0.757659920369, 1.37882996018, {1.60579280091, -0.903118886091, 0.101771877942, -0.0242139751146}},
  // hemispherical surface burst
  {BurstCurve::hemispherical_surface, KbParameter::incident_overpressure, 0.17, 100, -0.756579301809, 1.35034249993, {1.9422502013, -1.6958988741, -0.154159376846, 0.514060730593, 0.0988534365274, -0.293912623038, -0.0268112345019, 0.109097496421, 0.00162846756311, -0.0214631030242, 0.0001456723382, 0.00167847752266}},
  {BurstCurve::hemispherical_surface, KbParameter::incident_impulse, 0.17, 2.4099997637422717, 0.832468843425, 3.0760329666, {1.57159240621, -0.502992763686, 0.171335645235, 0.0450176963051, -0.0118964626402}},
  {BurstCurve::hemispherical_surface, KbParameter::incident_impulse, 2.4099997637422717, 100, -2.91358616806, 2.40697745406, {0.719852655584, -0.384519026965, -0.0260816706301, 0.00595798753822, 0.014544526107, -0.00663289334734, -0.00284189327204, 0.0013644816227}},
  {BurstCurve::hemispherical_surface, KbParameter::arrival_time, 0.17, 100, -0.755684472698, 1.37784223635, {-0.173607601251, 1.35706496258, 0.052492798645, -0.196563954086, -0.0601770052288, 0.0696360270891, 0.0215297490092, -0.0161658930785, -0.00232531970294, 0.00147752067524}},
  {BurstCurve::hemispherical_surface, KbParameter::positive_duration, 0.45, 2.539999902797195, -0.1790217052, 5.25099193925, {-0.728671776005, 0.130143717675, 0.134872511954, 0.0391574276906, -0.00475933664702, -0.00428144598008}},
  {BurstCurve::hemispherical_surface, KbParameter::positive_duration, 2.539999902797195, 6.999999355046411, -5.85909812338, 9.2996288611, {0.20096507334, -0.0297944268976, 0.030632954288, 0.0183405574086, -0.0173964666211, -0.00106321963633, 0.00562060030977, 0.0001618217499, -0.0006860188944}},
  {BurstCurve::hemispherical_surface, KbParameter::positive_duration, 6.999999355046411, 100, -4.92699491141, 3.46349745571, {0.572462469964, 0.0933035304009, -0.0005849420883, -0.00226884995013, -0.00295908591505, 0.00148029868929}},
  {BurstCurve::hemispherical_surface, KbParameter::reflected_overpressure, 0.17, 100, -0.789312405513, 1.36637719229, {2.56431321138, -2.21030870597, -0.218536586295, 0.895319589372, 0.24989009775, -0.569249436807, -0.11791682383, 0.224131161411, 0.0245620259375, -0.0455116002694, -0.00190930738887, 0.00361471193389}},
  {BurstCurve::hemispherical_surface, KbParameter::reflected_impulse, 0.17, 100, -0.781951689212, 1.33422049854, {1.75291677799, -0.949516092853, 0.112136118689, -0.0250659183287}},
  };
  // clang-format on
  return pieces;
}

constexpr double kLb = 0.45359237;          // kg, exact
constexpr double kFt = 0.3048;              // m, exact
constexpr double kPsi = 6894.757293168361;  // Pa, = 0.45359237 * 9.80665 / 0.0254^2

// Imperial value at metric z, converted to the SI units of kingery_bulmash_value.
double imperial_value(BurstCurve curve, KbParameter parameter, double z_m_kg13, bool& found) {
  const double cbrt_lb = std::cbrt(kLb);
  const double z_ft = z_m_kg13 * cbrt_lb / kFt;
  found = false;
  for (const ImperialPiece& piece : imperial_set()) {
    if (piece.curve != curve || piece.parameter != parameter) continue;
    if (z_ft < piece.z_min_ft_lb13 || z_ft > piece.z_max_ft_lb13) continue;
    const double u = piece.k0 + piece.k1 * std::log10(z_ft);
    double log10_y = 0.0;
    for (auto it = piece.c.rbegin(); it != piece.c.rend(); ++it)
      log10_y = log10_y * u + *it;
    const double y = std::pow(10.0, log10_y);
    found = true;
    switch (parameter) {
      case KbParameter::incident_overpressure:
      case KbParameter::reflected_overpressure:
        return y * kPsi;
      case KbParameter::incident_impulse:
      case KbParameter::reflected_impulse:
        return y * kPsi * 1e-3 / cbrt_lb;  // psi*ms/lb^(1/3) -> Pa*s/kg^(1/3)
      case KbParameter::arrival_time:
      case KbParameter::positive_duration:
        return y * 1e-3 / cbrt_lb;  // ms/lb^(1/3) -> s/kg^(1/3)
      case KbParameter::shock_velocity:
        return y * kFt * 1e3;
    }
  }
  return 0.0;
}

bool near_a_join(BurstCurve curve, KbParameter parameter, double z) {
  const ScaledRange range = kingery_bulmash_range(curve, parameter);
  for (double join : {0.792, 0.888, 2.28, 0.955, 1.01, 2.78})
    if (join > range.min_m_kg13 && join < range.max_m_kg13 && std::abs(z / join - 1.0) < 2e-3)
      return true;
  return false;
}

TEST(KingeryBulmash, MetricSetMatchesTheImperialTranscriptionThroughExactConversion) {
  int compared = 0;
  for (BurstCurve curve : kCurves) {
    for (KbParameter parameter : kAllParameters) {
      if (parameter == KbParameter::shock_velocity) continue;  // ConWep has no U fit
      const ScaledRange range = kingery_bulmash_range(curve, parameter);
      for (double z : log_grid(range.min_m_kg13 * 1.001, range.max_m_kg13 * 0.999, 300)) {
        if (near_a_join(curve, parameter, z)) continue;
        bool found = false;
        const double imperial = imperial_value(curve, parameter, z, found);
        if (!found) continue;  // the imperial ranges are rounded; skip the sliver at the ends
        EXPECT_NEAR(value(curve, parameter, z), imperial, 2e-5 * imperial)
            << "curve " << static_cast<int>(curve) << " parameter " << static_cast<int>(parameter)
            << " Z " << z;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 3000);
}

// --- Independent refit: Swisdak (1994), hemispherical surface burst --------------------------
// M. M. Swisdak, "Simplified Kingery Airblast Calculations", NSWC Indian Head (1994), tabulated
// per unit charge in the test table of the kingery-bulmash Python package (fcento100), with the
// sign of Swisdak's cubic i_r term as in his imperial set. Columns: Z (m/kg^(1/3)); t_a, t_o
// (ms/kg^(1/3)); P_so, P_r (kPa); i_s, i_r (kPa*ms/kg^(1/3)); U (km/s). Refit and original
// differ by up to 2 % (t_o near its joins), so agreement within 1.5 % at these points checks
// every coefficient of our surface set, higher terms included.
struct SwisdakRow {
  double z, ta, pso, pr, to, is, ir, u;
};
constexpr std::array kSwisdak = {
    SwisdakRow{0.5, 0.143, 4888, 39422, 0.281, 166.2, 2371, 2.178},
    SwisdakRow{1, 0.467, 1354, 8152, 1.72, 236.3, 884.7, 1.196},
    SwisdakRow{2, 1.693, 283.7, 1058, 2.053, 134.6, 363.8, 0.623},
    SwisdakRow{5, 8.242, 43.23, 100.9, 3.793, 59.31, 125.6, 0.398},
    SwisdakRow{10, 21.66, 14.89, 31.54, 4.779, 31.04, 59.33, 0.361},
    SwisdakRow{20, 49.93, 6.102, 12.44, 5.94, 15.89, 28.67, 0.349},
};

TEST(KingeryBulmash, SurfaceBurstAgreesWithSwisdaksRefit) {
  for (const SwisdakRow& row : kSwisdak) {
    const ScaledBlast s = kingery_bulmash(BurstCurve::hemispherical_surface, row.z);
    EXPECT_TRUE(s.in_validity_range);
    constexpr double tol = 0.015;
    EXPECT_NEAR(s.arrival_time_s_kg13 * 1e3, row.ta, tol * row.ta) << row.z;
    EXPECT_NEAR(s.incident_overpressure_pa * 1e-3, row.pso, tol * row.pso) << row.z;
    EXPECT_NEAR(s.reflected_overpressure_pa * 1e-3, row.pr, tol * row.pr) << row.z;
    EXPECT_NEAR(s.positive_duration_s_kg13 * 1e3, row.to, tol * row.to) << row.z;
    EXPECT_NEAR(s.incident_impulse_pa_s_kg13, row.is, tol * row.is) << row.z;
    EXPECT_NEAR(s.reflected_impulse_pa_s_kg13, row.ir, tol * row.ir) << row.z;
    EXPECT_NEAR(s.shock_velocity_m_s * 1e-3, row.u, tol * row.u) << row.z;
  }
}

TEST(KingeryBulmash, TenKilogramSurfaceBurstMatchesSwisdakValidationData) {
  // 10 kg TNT surface burst, Swisdak (1994) values as used in the blastFoam validation data
  // (KingeryBulmash wedge case): R (m), P_so (kPa), i_s (kPa*ms), t_a (ms).
  struct Row {
    double r, pso, is, ta;
  };
  constexpr std::array rows = {Row{1, 5472, 360.3, 0.2744}, Row{2, 1585, 497, 0.8809},
                               Row{3, 653.1, 403.7, 1.855}, Row{5, 202.4, 250.6, 4.811},
                               Row{7, 97.98, 185.9, 8.775}, Row{10, 49.27, 136.3, 15.82}};
  const Charge charge{10.0, Burst::surface, SurfaceBurstModel::hemispherical};
  for (const Row& row : rows) {
    const BlastPoint p = blast_point(charge, row.r);
    EXPECT_NEAR(p.incident_overpressure_pa * 1e-3, row.pso, 0.015 * row.pso) << row.r;
    EXPECT_NEAR(p.incident_impulse_pa_s, row.is, 0.015 * row.is) << row.r;
    EXPECT_NEAR(p.arrival_time_s * 1e3, row.ta, 0.015 * row.ta) << row.r;
  }
}

TEST(KingeryBulmash, FarFieldMatchesTheDodK328Criterion) {
  // DoD explosives-safety K328 (328 ft/lb^(1/3) = 130.1 m/kg^(1/3)) corresponds to 0.0655 psi
  // (0.4516 kPa) side-on overpressure of a surface burst (DoD 6055.09-M). That is beyond the
  // fits' range (40), so it exercises the far continuation; a plain acoustic 1/Z decay would give
  // 0.73 kPa here, 60 % too much.
  const double z = 328.0 * kFt / std::cbrt(kLb);
  bool in_range = true;
  const double pso = kingery_bulmash_value(BurstCurve::hemispherical_surface,
                                           KbParameter::incident_overpressure, z, &in_range);
  EXPECT_FALSE(in_range);
  EXPECT_NEAR(pso * 1e-3, 0.4516, 0.08 * 0.4516);
}

// --- Physics consistency ---------------------------------------------------------------------

TEST(KingeryBulmash, ReflectedPressureMatchesRankineHugoniotOverTheMiddleRange) {
  // Thesis eq. 2.29 (ideal gas) against the fitted P_r: real-gas effects only matter above about
  // 1 MPa, so over Z = 1..40 the two must agree closely.
  for (BurstCurve curve : kCurves) {
    for (double z : log_grid(1.0, 40.0, 60)) {
      const ScaledBlast s = kingery_bulmash(curve, z);
      const double rh = rh_reflected_overpressure_pa(s.incident_overpressure_pa);
      EXPECT_NEAR(s.reflected_overpressure_pa, rh, 0.03 * rh) << z;
    }
  }
}

TEST(KingeryBulmash, ShockVelocityMatchesRankineHugoniot) {
  // Eq. 2.15 from the fitted P_so against the fitted U (the free-air U fit was chosen among
  // transcriptions partly by this test: a published typo in C7 fails it by 50 %).
  for (BurstCurve curve : kCurves) {
    for (double z : log_grid(0.4, 40.0, 80)) {
      const ScaledBlast s = kingery_bulmash(curve, z);
      const double rh = rh_shock_velocity_m_s(s.incident_overpressure_pa);
      EXPECT_NEAR(s.shock_velocity_m_s, rh, 0.03 * rh) << z;
    }
  }
}

TEST(KingeryBulmash, NormalReflectionCoefficientRisesWithPressure) {
  // C_R(0) = P_r / P_so goes from about 2 (acoustic) towards 8 and beyond (real gas, near field).
  for (BurstCurve curve : kCurves) {
    const ScaledBlast far = kingery_bulmash(curve, 40.0);
    EXPECT_NEAR(far.reflected_overpressure_pa / far.incident_overpressure_pa, 2.0, 0.1);
    const ScaledBlast near = kingery_bulmash(curve, 0.1);
    EXPECT_GT(near.reflected_overpressure_pa / near.incident_overpressure_pa, 8.0);
  }
}

// --- Shape of the curves ---------------------------------------------------------------------

TEST(KingeryBulmash, PiecesJoinWithinTheFitsOwnTolerance) {
  // The published pieces do not meet exactly (ConWep's imperial set and Swisdak's refit jump by
  // the same amounts). Measured jumps: free-air i_s -0.40 %, t_o +0.92 % and +0.09 %; surface
  // i_s +0.52 %, t_o -1.81 % and +0.88 %. A wrong coefficient gives tens of percent.
  struct Join {
    BurstCurve curve;
    KbParameter parameter;
    double z;
    double max_jump;
  };
  constexpr std::array joins = {
      Join{BurstCurve::spherical_free_air, KbParameter::incident_impulse, 0.792, 0.005},
      Join{BurstCurve::spherical_free_air, KbParameter::positive_duration, 0.888, 0.011},
      Join{BurstCurve::spherical_free_air, KbParameter::positive_duration, 2.28, 0.002},
      Join{BurstCurve::hemispherical_surface, KbParameter::incident_impulse, 0.955, 0.006},
      Join{BurstCurve::hemispherical_surface, KbParameter::positive_duration, 1.01, 0.02},
      Join{BurstCurve::hemispherical_surface, KbParameter::positive_duration, 2.78, 0.01},
  };
  for (const Join& join : joins) {
    const double below = value(join.curve, join.parameter, join.z * (1 - 1e-12));
    const double above = value(join.curve, join.parameter, join.z * (1 + 1e-12));
    EXPECT_NEAR(above / below, 1.0, join.max_jump) << join.z;
    EXPECT_GT(std::abs(above / below - 1.0), 1e-5) << "join at " << join.z << " not crossed";
  }
}

TEST(KingeryBulmash, MonotoneInScaledDistance) {
  for (BurstCurve curve : kCurves) {
    const ScaledRange range = kingery_bulmash_range(curve, KbParameter::incident_overpressure);
    ScaledBlast previous = kingery_bulmash(curve, range.min_m_kg13);
    for (double z : log_grid(range.min_m_kg13 * 1.01, 40.0, 400)) {
      const ScaledBlast s = kingery_bulmash(curve, z);
      EXPECT_LT(s.incident_overpressure_pa, previous.incident_overpressure_pa) << z;
      EXPECT_LT(s.reflected_overpressure_pa, previous.reflected_overpressure_pa) << z;
      EXPECT_LT(s.reflected_impulse_pa_s_kg13, previous.reflected_impulse_pa_s_kg13) << z;
      EXPECT_LT(s.shock_velocity_m_s, previous.shock_velocity_m_s) << z;
      EXPECT_GT(s.arrival_time_s_kg13, previous.arrival_time_s_kg13) << z;
      // Incident impulse peaks near Z = 1 (the fireball region) and falls beyond it; the
      // positive duration grows in the far field.
      if (z > 1.2) {
        EXPECT_LT(s.incident_impulse_pa_s_kg13, previous.incident_impulse_pa_s_kg13) << z;
      }
      if (z > 3.0) {
        EXPECT_GT(s.positive_duration_s_kg13, previous.positive_duration_s_kg13) << z;
      }
      previous = s;
    }
  }
}

TEST(BlastPoint, WaveReachIsWhereTheArrivalPassesTheTime) {
  // Inside the fits (100 kg at 0.1 s: about 40 m), beyond them (at 2 s: about 700 m, arrival
  // continued at the far end's shock speed) and for a surface burst.
  Charge surface{100.0};
  surface.burst = Burst::surface;
  for (const auto& [charge, time] :
       {std::pair{Charge{100.0}, 0.1}, std::pair{Charge{100.0}, 2.0}, std::pair{surface, 0.05}}) {
    const double reach = wave_reach_m(charge, time);
    EXPECT_GE(blast_point(charge, reach).arrival_time_s, time);
    EXPECT_LT(blast_point(charge, reach * (1.0 - 2e-6)).arrival_time_s, time);
  }
  EXPECT_GT(wave_reach_m(Charge{100.0}, 2.0), 600.0);
  EXPECT_LT(wave_reach_m(Charge{100.0}, 2.0), 800.0);
}

TEST(BlastPoint, FollowsCubeRootScaling) {
  // Thesis eq. 2.19: R1 / R2 = (W1 / W2)^(1/3) gives the same pressures; times and impulses
  // scale with the cube root of the charge.
  const Charge small{8.0};
  const Charge large{1000.0};
  const double ratio = std::cbrt(1000.0 / 8.0);  // 5
  for (double r : {1.0, 3.0, 10.0, 40.0}) {
    const BlastPoint a = blast_point(small, r);
    const BlastPoint b = blast_point(large, r * ratio);
    EXPECT_NEAR(a.scaled_distance_m_kg13, b.scaled_distance_m_kg13,
                1e-12 * b.scaled_distance_m_kg13);
    EXPECT_NEAR(b.incident_overpressure_pa, a.incident_overpressure_pa,
                1e-9 * a.incident_overpressure_pa);
    EXPECT_NEAR(b.reflected_overpressure_pa, a.reflected_overpressure_pa,
                1e-9 * a.reflected_overpressure_pa);
    EXPECT_NEAR(b.arrival_time_s, ratio * a.arrival_time_s, 1e-9 * b.arrival_time_s);
    EXPECT_NEAR(b.positive_duration_s, ratio * a.positive_duration_s, 1e-9 * b.positive_duration_s);
    EXPECT_NEAR(b.incident_impulse_pa_s, ratio * a.incident_impulse_pa_s,
                1e-9 * b.incident_impulse_pa_s);
    EXPECT_NEAR(b.reflected_impulse_pa_s, ratio * a.reflected_impulse_pa_s,
                1e-9 * b.reflected_impulse_pa_s);
    EXPECT_DOUBLE_EQ(b.shock_velocity_m_s, a.shock_velocity_m_s);
  }
}

TEST(BlastPoint, SurfaceBurstModelsAgreeRoughly) {
  // The 1.8 x free-air shortcut (thesis §2.5.1) against the hemispherical curves: a comparison,
  // not a fit. Over Z = 1..40 the side-on pressures agree within 15 %.
  const Charge hemispherical{100.0, Burst::surface, SurfaceBurstModel::hemispherical};
  const Charge factor{100.0, Burst::surface, SurfaceBurstModel::factor_1_8};
  for (double r : log_grid(5.0, 180.0, 30)) {
    const BlastPoint a = blast_point(hemispherical, r);
    const BlastPoint b = blast_point(factor, r);
    EXPECT_NEAR(b.incident_overpressure_pa, a.incident_overpressure_pa,
                0.15 * a.incident_overpressure_pa)
        << r;
    EXPECT_DOUBLE_EQ(b.tnt_equivalent_kg, 100.0);
    EXPECT_NEAR(b.scaled_distance_m_kg13, r / std::cbrt(180.0), 1e-12 * r);
  }
}

TEST(BlastPoint, DynamicPressureFromRankineHugoniot) {
  const BlastPoint p = blast_point(Charge{100.0}, 15.0);
  EXPECT_DOUBLE_EQ(p.dynamic_pressure_pa, rh_dynamic_pressure_pa(p.incident_overpressure_pa));
  EXPECT_GT(p.dynamic_pressure_pa, 0.0);
}

TEST(KingeryBulmash, AllParametersAtOnceEqualsEachParameterAlone) {
  // kingery_bulmash() evaluates the seven fits side by side where all are in range; it must give
  // what kingery_bulmash_value() gives for each parameter alone, in range and out.
  for (BurstCurve curve : kCurves) {
    for (double z : log_grid(1e-3, 1e3, 2000)) {
      const ScaledBlast all = kingery_bulmash(curve, z);
      bool every_inside = true;
      const double alone[] = {kingery_bulmash_value(curve, KbParameter::incident_overpressure, z),
                              kingery_bulmash_value(curve, KbParameter::incident_impulse, z),
                              kingery_bulmash_value(curve, KbParameter::arrival_time, z),
                              kingery_bulmash_value(curve, KbParameter::positive_duration, z),
                              kingery_bulmash_value(curve, KbParameter::reflected_overpressure, z),
                              kingery_bulmash_value(curve, KbParameter::reflected_impulse, z),
                              kingery_bulmash_value(curve, KbParameter::shock_velocity, z)};
      for (KbParameter parameter : kAllParameters) {
        bool inside = true;
        kingery_bulmash_value(curve, parameter, z, &inside);
        every_inside = every_inside && inside;
      }
      const double together[] = {all.incident_overpressure_pa,  all.incident_impulse_pa_s_kg13,
                                 all.arrival_time_s_kg13,       all.positive_duration_s_kg13,
                                 all.reflected_overpressure_pa, all.reflected_impulse_pa_s_kg13,
                                 all.shock_velocity_m_s};
      for (int p = 0; p < kKbParameterCount; ++p)
        EXPECT_NEAR(together[p], alone[p], 1e-13 * alone[p]) << "Z " << z << " parameter " << p;
      EXPECT_EQ(all.in_validity_range, every_inside) << z;
    }
  }
}

// --- Outside the fitted range ----------------------------------------------------------------

TEST(KingeryBulmash, OutsideTheRangeIsFlaggedFiniteAndContinuous) {
  for (BurstCurve curve : kCurves) {
    for (KbParameter parameter : kAllParameters) {
      const ScaledRange range = kingery_bulmash_range(curve, parameter);
      bool in_range = true;
      for (double z : {range.min_m_kg13 * 0.5, range.min_m_kg13 * 1e-3, range.max_m_kg13 * 2.0,
                       range.max_m_kg13 * 1e4}) {
        const double v = kingery_bulmash_value(curve, parameter, z, &in_range);
        EXPECT_FALSE(in_range) << z;
        EXPECT_TRUE(std::isfinite(v) && v > 0.0) << z;
      }
      kingery_bulmash_value(curve, parameter, range.min_m_kg13, &in_range);
      EXPECT_TRUE(in_range);
      // Continuous where the continuation takes over.
      for (double edge : {range.min_m_kg13, range.max_m_kg13}) {
        const double inside = value(curve, parameter, edge);
        const double outside =
            value(curve, parameter, edge * (edge == range.min_m_kg13 ? 0.9999 : 1.0001));
        EXPECT_NEAR(outside, inside, 2e-4 * inside) << edge;
      }
    }
    EXPECT_FALSE(kingery_bulmash(curve, 100.0).in_validity_range);
    EXPECT_TRUE(kingery_bulmash(curve, 5.0).in_validity_range);
  }
}

TEST(KingeryBulmash, FarContinuationFollowsTheLastOctavesPowerLaw) {
  const auto p = [](double z) {
    return value(BurstCurve::spherical_free_air, KbParameter::incident_overpressure, z);
  };
  // The slope through [20, 40] carries on: equal ratios over equal factors in Z.
  EXPECT_NEAR(p(80.0) / p(40.0), p(40.0) / p(20.0), 1e-9);
  EXPECT_NEAR(p(160.0) / p(80.0), p(40.0) / p(20.0), 1e-9);
  // Arrival time keeps growing at the far-end shock velocity (close to the speed of sound).
  const double t40 = value(BurstCurve::spherical_free_air, KbParameter::arrival_time, 40.0);
  const double t140 = value(BurstCurve::spherical_free_air, KbParameter::arrival_time, 140.0);
  const double u40 = value(BurstCurve::spherical_free_air, KbParameter::shock_velocity, 40.0);
  EXPECT_NEAR(t140 - t40, 100.0 / u40, 1e-9);
  EXPECT_NEAR(u40, 343.0, 5.0);
}

}  // namespace
}  // namespace brisance::blast
