// math.cpp: Transform constructors and composition.
#include "ltm/core/math.h"

namespace ltm {

bool Transform::is_identity() const {
    const Transform id;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            if (m[r][c] != id.m[r][c]) return false;
    return true;
}

Transform Transform::translate(Vec3f t) {
    Transform x;
    x.m[0][3] = t.x, x.m[1][3] = t.y, x.m[2][3] = t.z;
    return x;
}

Transform Transform::scale(Vec3f s) {
    Transform x;
    x.m[0][0] = s.x, x.m[1][1] = s.y, x.m[2][2] = s.z;
    return x;
}

Transform Transform::rotate(Vec3f axis, float degrees) {
    const Vec3f a = normalize(axis);
    const double rad = double(degrees) * 3.14159265358979323846 / 180.0;
    const float s = float(std::sin(rad)), c = float(std::cos(rad)), ic = 1.f - c;
    Transform x;   // Rodrigues' formula
    x.m[0][0] = a.x * a.x * ic + c,       x.m[0][1] = a.x * a.y * ic - a.z * s, x.m[0][2] = a.x * a.z * ic + a.y * s;
    x.m[1][0] = a.y * a.x * ic + a.z * s, x.m[1][1] = a.y * a.y * ic + c,       x.m[1][2] = a.y * a.z * ic - a.x * s;
    x.m[2][0] = a.z * a.x * ic - a.y * s, x.m[2][1] = a.z * a.y * ic + a.x * s, x.m[2][2] = a.z * a.z * ic + c;
    return x;
}

Transform operator*(const Transform &a, const Transform &b) {
    Transform r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            float v = j == 3 ? a.m[i][3] : 0.f;
            for (int k = 0; k < 3; ++k) v += a.m[i][k] * b.m[k][j];
            r.m[i][j] = v;
        }
    }
    return r;
}

}  // namespace ltm
