#include "sim/blast/kingery_bulmash.hpp"

#include <array>
#include <cassert>
#include <cmath>
#include <numbers>
#include <span>

namespace brisance::blast {

namespace {

// One polynomial piece: U = k0 + k1 log10(Z), log10(Y) = sum_i c[i] U^i on [z_min, z_max].
struct Piece {
  double z_min;
  double z_max;
  double k0;
  double k1;
  std::array<double, 15> c;
  int count;  // number of c coefficients used
};

struct Fit {
  std::array<Piece, 3> pieces;
  int count;
  double to_si;  // factor from the fit's unit to SI
};

constexpr double kKpa = 1e3;     // kPa -> Pa
constexpr double kKpaMs = 1.0;   // kPa*ms -> Pa*s
constexpr double kMs = 1e-3;     // ms -> s
constexpr double kMPerMs = 1e3;  // m/ms -> m/s

// Coefficients: the metric Kingery–Bulmash set as printed in UFC 3-340-02 (2008) and in the
// "NATO AASTP-1" lineage of ConWep re-implementations, cross-checked against a second public
// transcription and against the imperial set through the exact unit conversions, and against
// Swisdak's independent refit ("Simplified Kingery Airblast Calculations", NSWC 1994) to within
// about 1 %; see tests/sim/blast/kingery_bulmash_test.cpp. Ranges in m/kg^(1/3).
// Units of the fits: kPa; kPa*ms/kg^(1/3); ms/kg^(1/3); m/ms.

// clang-format off
constexpr std::array<Fit, kKbParameterCount> kSpherical = {{
  // incident overpressure, kPa
  {{{{0.0531, 40.0, -0.214362789151, 1.35034249993,
      {2.611368669, -1.69012801396, 0.00804973591951, 0.336743114941, -0.00516226351334,
       -0.0809228619888, -0.00478507266747, 0.00793030472242, 0.0007684469735}, 9}}}, 1, kKpa},
  // incident impulse, kPa*ms/kg^(1/3)
  {{{{0.0531, 0.792, 2.34723921354, 3.24299066475,
      {2.38830516757, -0.443749377691, 0.168825414684, 0.0348138030308, -0.010435192824}, 5},
     {0.792, 40.0, -1.75305660315, 2.30629231803,
      {1.55197227115, -0.40463292088, -0.0142721946082, 0.00912366316617, -0.0006750681404,
       -0.00800863718901, 0.00314819515931, 0.00152044783382, -0.0007470265899}, 9}}}, 2, kKpaMs},
  // arrival time, ms/kg^(1/3)
  {{{{0.0531, 40.0, -0.253273111999, 1.37407043777,
      {0.0720707787637, 1.36456871214, -0.0570035692784, -0.182832224796, 0.0118851436014,
       0.0432648687627, -0.0007997367834, -0.00436073555033}, 8}}}, 1, kMs},
  // positive duration, ms/kg^(1/3)
  {{{{0.147, 0.888, 2.26367268496, 5.11588554305,
      {-0.686608550419, 0.164953518069, 0.127788499497, 0.00291430135946, 0.00187957449227,
       0.0173413962543, 0.00269739758043, -0.00361976502798, -0.00100926577934}, 9},
     {0.888, 2.28, -1.33361206714, 9.2996288611,
      {0.23031841078, -0.0297944268969, 0.0306329542941, 0.018340557407, -0.0173964666286,
       -0.00106321963576, 0.0056206003128, 0.0001618217499, -0.0006860188944}, 9},
     {2.28, 40.0, -3.13005805346, 3.1524725364,
      {0.621036276475, 0.0967031995552, -0.00801302059667, 0.00482705779732, 0.00187587272287,
       -0.00246738509321, -0.000841116668, 0.0006193291052}, 8}}}, 3, kMs},
  // reflected overpressure, kPa
  {{{{0.0531, 40.0, -0.214362789151, 1.35034249993,
      {3.22958031387, -2.21400538997, 0.035119031446, 0.657599992109, 0.0141818951887,
       -0.243076636231, -0.0158699803158, 0.0492741184234, 0.00227639644004,
       -0.00397126276058}, 10}}}, 1, kKpa},
  // reflected impulse, kPa*ms/kg^(1/3)
  {{{{0.0531, 40.0, -0.204004553231, 1.37882996018,
      {2.55875660396, -0.903118886091, 0.101771877942, -0.0242139751146}, 4}}}, 1, kKpaMs},
  // shock velocity, m/ms
  {{{{0.0531, 40.0, -0.214362789151, 1.35034249993,
      {-0.144615443471, -0.650507560471, 0.291320654009, 0.307916322787, -0.183361123489,
       -0.197740454538, 0.0909119559768, 0.0898926178054, -0.0287370990248, -0.0248730221702,
       0.00496311705671, 0.00372242076361, -0.0003533736952, -0.0002292913709}, 14}}}, 1,
   kMPerMs},
}};

constexpr std::array<Fit, kKbParameterCount> kHemispherical = {{
  // incident overpressure, kPa
  {{{{0.0674, 40.0, -0.214362789151, 1.35034249993,
      {2.78076916577, -1.6958988741, -0.154159376846, 0.514060730593, 0.0988534365274,
       -0.293912623038, -0.0268112345019, 0.109097496421, 0.00162846756311, -0.0214631030242,
       0.0001456723382, 0.00167847752266}, 12}}}, 1, kKpa},
  // incident impulse, kPa*ms/kg^(1/3)
  {{{{0.0674, 0.955, 2.06761908721, 3.0760329666,
      {2.52455620925, -0.502992763686, 0.171335645235, 0.0450176963051, -0.0118964626402}, 5},
     {0.955, 40.0, -1.94708846747, 2.40697745406,
      {1.67281645863, -0.384519026965, -0.0260816706301, 0.00595798753822, 0.0145445261077,
       -0.00663289334734, -0.00284189327204, 0.0013644816227}, 8}}}, 2, kKpaMs},
  // arrival time, ms/kg^(1/3)
  {{{{0.0674, 40.0, -0.202425716178, 1.37784223635,
      {-0.0591634288046, 1.35706496258, 0.052492798645, -0.196563954086, -0.0601770052288,
       0.0696360270891, 0.0215297490092, -0.0161658930785, -0.00232531970294,
       0.00147752067524}, 10}}}, 1, kMs},
  // positive duration, ms/kg^(1/3)
  {{{{0.178, 1.01, 1.92946154068, 5.25099193925,
      {-0.614227603559, 0.130143717675, 0.134872511954, 0.0391574276906, -0.00475933664702,
       -0.00428144598008}, 6},
     {1.01, 2.78, -2.12492525216, 9.2996288611,
      {0.315409245784, -0.0297944268976, 0.030632954288, 0.0183405574086, -0.0173964666211,
       -0.00106321963633, 0.00562060030977, 0.0001618217499, -0.0006860188944}, 9},
     {2.78, 40.0, -3.53626218091, 3.46349745571,
      {0.686906642409, 0.0933035304009, -0.0005849420883, -0.00226884995013,
       -0.00295908591505, 0.00148029868929}, 6}}}, 3, kMs},
  // reflected overpressure, kPa
  {{{{0.0674, 40.0, -0.240657322658, 1.36637719229,
      {3.40283217581, -2.21030870597, -0.218536586295, 0.895319589372, 0.24989009775,
       -0.569249436807, -0.11791682383, 0.224131161411, 0.0245620259375, -0.0455116002694,
       -0.00190930738887, 0.00361471193389}, 12}}}, 1, kKpa},
  // reflected impulse, kPa*ms/kg^(1/3)
  {{{{0.0674, 40.0, -0.246208804814, 1.33422049854,
      {2.70588058103, -0.949516092853, 0.112136118689, -0.0250659183287}, 4}}}, 1, kKpaMs},
  // shock velocity, m/ms
  {{{{0.0674, 40.0, -0.202425716178, 1.37784223635,
      {-0.06621072854, -0.698029762594, 0.158916781906, 0.443812098136, -0.113402023921,
       -0.369887075049, 0.129230567449, 0.19857981197, -0.0867636217397, -0.0620391900135,
       0.0307482926566, 0.0102657234407, -0.00546533250772, -0.000693180974,
       0.0003847494916}, 15}}}, 1, kMPerMs},
}};
// clang-format on

const Fit& fit_for(BurstCurve curve, KbParameter parameter) {
  const auto& fits = curve == BurstCurve::spherical_free_air ? kSpherical : kHemispherical;
  return fits[static_cast<std::size_t>(parameter)];
}

// The fit's value in SI at a z inside its range, given log10(z).
double evaluate(const Fit& fit, double z, double log10_z) {
  int index = 0;
  while (index + 1 < fit.count && z >= fit.pieces[index].z_max)
    ++index;
  const Piece& piece = fit.pieces[index];
  const double u = piece.k0 + piece.k1 * log10_z;
  double log10_y = 0.0;
  for (int i = piece.count - 1; i >= 0; --i)
    log10_y = log10_y * u + piece.c[i];
  return fit.to_si * std::exp(std::numbers::ln10 * log10_y);
}

ScaledRange range_of(const Fit& fit) {
  return {fit.pieces[0].z_min, fit.pieces[fit.count - 1].z_max};
}

// Value with the out-of-range continuation described in the header.
double value_at(BurstCurve curve, KbParameter parameter, double z, double log10_z, bool& in_range) {
  const Fit& fit = fit_for(curve, parameter);
  const ScaledRange range = range_of(fit);
  if (z >= range.min_m_kg13 && z <= range.max_m_kg13) return evaluate(fit, z, log10_z);
  in_range = false;
  if (z < range.min_m_kg13) {
    const double at_end = evaluate(fit, range.min_m_kg13, std::log10(range.min_m_kg13));
    return parameter == KbParameter::arrival_time ? at_end * z / range.min_m_kg13 : at_end;
  }
  const double far = range.max_m_kg13;
  const double at_end = evaluate(fit, far, std::log10(far));
  switch (parameter) {
    case KbParameter::arrival_time: {
      const Fit& velocity = fit_for(curve, KbParameter::shock_velocity);
      return at_end + (z - far) / evaluate(velocity, far, std::log10(far));
    }
    case KbParameter::shock_velocity:
      return at_end;
    default: {
      // Power law through the last octave of the fit (secant slope in log-log).
      const double half = 0.5 * far;
      const double slope =
          std::log(at_end / evaluate(fit, half, std::log10(half))) / std::numbers::ln2;
      return at_end * std::pow(z / far, slope);
    }
  }
}

}  // namespace

ScaledRange kingery_bulmash_range(BurstCurve curve, KbParameter parameter) {
  return range_of(fit_for(curve, parameter));
}

double kingery_bulmash_value(BurstCurve curve, KbParameter parameter, double z, bool* in_range) {
  assert(z > 0.0 && std::isfinite(z));
  bool inside = true;
  const double value = value_at(curve, parameter, z, std::log10(z), inside);
  if (in_range != nullptr) *in_range = inside;
  return value;
}

ScaledBlast kingery_bulmash(BurstCurve curve, double z) {
  assert(z > 0.0 && std::isfinite(z));
  const auto& fits = curve == BurstCurve::spherical_free_air ? kSpherical : kHemispherical;
  const double log10_z = std::log10(z);
  std::array<double, kKbParameterCount> values{};
  bool inside = true;
  // Inside every parameter's range (all end at Z = 40; the duration starts latest), the seven
  // polynomials run side by side: seven independent Horner chains overlap in the pipeline,
  // where one after another each would wait on its own multiply-add latency.
  const double common_min =
      fits[static_cast<std::size_t>(KbParameter::positive_duration)].pieces[0].z_min;
  if (z >= common_min && z <= 40.0) {
    std::array<const Piece*, kKbParameterCount> pieces{};
    std::array<double, kKbParameterCount> u{};
    std::array<double, kKbParameterCount> log10_y{};
    for (int p = 0; p < kKbParameterCount; ++p) {
      const Fit& fit = fits[p];
      int index = 0;
      while (index + 1 < fit.count && z >= fit.pieces[index].z_max)
        ++index;
      pieces[p] = &fit.pieces[index];
      u[p] = pieces[p]->k0 + pieces[p]->k1 * log10_z;
    }
    // Unused high coefficients are zero, so every chain may start at the top.
    for (int i = static_cast<int>(Piece{}.c.size()) - 1; i >= 0; --i)
      for (int p = 0; p < kKbParameterCount; ++p)
        log10_y[p] = log10_y[p] * u[p] + pieces[p]->c[i];
    for (int p = 0; p < kKbParameterCount; ++p)
      values[p] = fits[p].to_si * std::exp(std::numbers::ln10 * log10_y[p]);
  } else {
    for (int p = 0; p < kKbParameterCount; ++p)
      values[p] = value_at(curve, static_cast<KbParameter>(p), z, log10_z, inside);
  }
  ScaledBlast out;
  out.incident_overpressure_pa = values[static_cast<int>(KbParameter::incident_overpressure)];
  out.incident_impulse_pa_s_kg13 = values[static_cast<int>(KbParameter::incident_impulse)];
  out.arrival_time_s_kg13 = values[static_cast<int>(KbParameter::arrival_time)];
  out.positive_duration_s_kg13 = values[static_cast<int>(KbParameter::positive_duration)];
  out.reflected_overpressure_pa = values[static_cast<int>(KbParameter::reflected_overpressure)];
  out.reflected_impulse_pa_s_kg13 = values[static_cast<int>(KbParameter::reflected_impulse)];
  out.shock_velocity_m_s = values[static_cast<int>(KbParameter::shock_velocity)];
  out.in_validity_range = inside;
  return out;
}

}  // namespace brisance::blast
