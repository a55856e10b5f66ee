// field_metrics.cpp: level, chroma, correlation and the flat-oracle floor of an E⁺ field.
#include "ltm/eval/field_metrics.h"

#include <algorithm>
#include <cmath>

#include "ltm/core/error.h"

namespace ltm {

double luminance(const Color3d &c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

Color3d mean_color(const float *rows, size_t n) {
    Color3d m{0, 0, 0};
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) m[size_t(c)] += double(rows[3 * i + size_t(c)]);
    if (n > 0)
        for (auto &v : m) v /= double(n);
    return m;
}

Color3d centred_log(const Color3d &x) {
    const double floor = 1e-6 * std::max({x[0], x[1], x[2], 1e-300});
    Color3d l;
    for (size_t c = 0; c < 3; ++c) l[c] = std::log(std::max(x[c], floor));
    const double g = (l[0] + l[1] + l[2]) / 3.0;
    for (auto &v : l) v -= g;
    return l;
}

Color3d mean_color(const std::vector<Vec3f> &rows) {
    static_assert(sizeof(Vec3f) == 3 * sizeof(float), "Vec3f rows must be packed");
    return mean_color(reinterpret_cast<const float *>(rows.data()), rows.size());
}

double chroma_error(const Color3d &a, const Color3d &b) {
    const Color3d la = centred_log(a), lb = centred_log(b);
    double s = 0;
    for (size_t c = 0; c < 3; ++c) s += (la[c] - lb[c]) * (la[c] - lb[c]);
    return std::sqrt(s / 3.0);
}

double blue_share(const Color3d &c) {
    const double s = c[0] + c[1] + c[2];
    return s > 0 ? c[2] / s : 0.0;
}

FieldMetrics compare_fields(const float *pred, const float *ref, size_t n) {
    if (n == 0) LTM_THROW("compare_fields: no points");
    for (size_t i = 0; i < 3 * n; ++i)
        if (!std::isfinite(pred[i]) || !std::isfinite(ref[i]))
            LTM_THROW("compare_fields: non-finite value at point ", i / 3, " (", std::isfinite(pred[i]) ? "reference" : "prediction", ")");
    FieldMetrics f;
    const Color3d mp = mean_color(pred, n), mr = mean_color(ref, n);
    const double yp = luminance(mp), yr = luminance(mr);
    f.level_ratio = yr > 0 ? yp / yr : (yp > 0 ? INFINITY : 1.0);
    f.chroma_error = chroma_error(mp, mr);
    // Pearson correlation of per-point luminance, two passes in double.
    double sxy = 0, sxx = 0, syy = 0, se = 0, sf = 0;
    for (size_t i = 0; i < n; ++i) {
        const float *p = pred + 3 * i, *r = ref + 3 * i;
        const double x = luminance(Color3d{p[0], p[1], p[2]}) - yp, y = luminance(Color3d{r[0], r[1], r[2]}) - yr;
        sxy += x * y, sxx += x * x, syy += y * y;
        for (size_t c = 0; c < 3; ++c) {
            se += (double(p[c]) - double(r[c])) * (double(p[c]) - double(r[c]));
            sf += (mr[c] - double(r[c])) * (mr[c] - double(r[c]));
        }
    }
    f.luminance_correlation = sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0.0;
    const double norm = yr > 0 ? 1.0 / (3.0 * double(n) * yr * yr) : 1.0 / (3.0 * double(n));
    f.mse = se * norm;
    f.flat_mse = sf * norm;
    return f;
}

FieldMetrics compare_fields(const std::vector<Vec3f> &pred, const std::vector<Vec3f> &ref) {
    if (pred.size() != ref.size()) LTM_THROW("compare_fields: ", pred.size(), " predictions for ", ref.size(), " reference points");
    return compare_fields(reinterpret_cast<const float *>(pred.data()), reinterpret_cast<const float *>(ref.data()), pred.size());
}

}  // namespace ltm
