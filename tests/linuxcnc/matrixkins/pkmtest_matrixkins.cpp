// pkmtest_matrixkins: a reference kinematics module for the differential test of pkmkins against
// matrixkins' equations (tests/linuxcnc/run-differential), which Debian's LinuxCNC 2.9 does not
// have. Written from matrixkins' manual page (the third source document): joints = C * (X Y Z),
// the joints after the third passed through as A B C; forward solves C * (X Y Z) = joints.
// The coefficients are HAL parameters named as matrixkins' (matrixkins.C_xx .. C_zz, default the
// identity), so a matrixkins configuration's `setp matrixkins.C_xy ...` lines run unchanged;
// only the module's name differs, so that it cannot clash with a real matrixkins.so.
//
//   [KINS] KINEMATICS = pkmtest_matrixkins
#include <cerrno>
#include <cmath>

#include "emcpos.h"  // C++ parts of posemath first: kinematics.h is C without extern "C"
#include "hal.h"
#include "rtapi.h"
#include "rtapi_app.h"
extern "C" {
#include "kinematics.h"
}

MODULE_AUTHOR("The pkmkit developers");
MODULE_DESCRIPTION("matrixkins' equations, for pkmkit's differential tests");
MODULE_LICENSE("MIT");

namespace {

// C, row by row: joint r = sum over c of C[r][c] * axis c.
struct Coefficients {
  hal_float_t c[3][3];
};

int component = -1;
Coefficients* coefficients = nullptr;

// The matrix C as plain numbers, and its determinant.
struct Matrix {
  double m[3][3];
  double determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
};

Matrix current() {
  Matrix matrix{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) matrix.m[r][c] = coefficients->c[r][c];
  }
  return matrix;
}

}  // namespace

extern "C" {

// Joints from the pose: C times X Y Z; A B C pass through.
int kinematicsInverse(const EmcPose* pose, double* joints, const KINEMATICS_INVERSE_FLAGS*,
                      KINEMATICS_FORWARD_FLAGS*) {
  const Matrix c = current();
  const double axis[3] = {pose->tran.x, pose->tran.y, pose->tran.z};
  for (int r = 0; r < 3; ++r) {
    joints[r] = c.m[r][0] * axis[0] + c.m[r][1] * axis[1] + c.m[r][2] * axis[2];
  }
  joints[3] = pose->a;
  joints[4] = pose->b;
  joints[5] = pose->c;
  return 0;
}

// The pose from the joints: C's inverse (the adjugate over the determinant) times the joints.
int kinematicsForward(const double* joints, EmcPose* pose, const KINEMATICS_FORWARD_FLAGS*,
                      KINEMATICS_INVERSE_FLAGS*) {
  const Matrix c = current();
  const double det = c.determinant();
  if (!(std::fabs(det) > 1e-12)) return -1;
  const auto cofactor = [&](int row, int col) {
    const int r0 = (row + 1) % 3, r1 = (row + 2) % 3, c0 = (col + 1) % 3, c1 = (col + 2) % 3;
    return c.m[r0][c0] * c.m[r1][c1] - c.m[r0][c1] * c.m[r1][c0];
  };
  double axis[3];
  for (int a = 0; a < 3; ++a) {
    // (C^-1)[a][j] = cofactor(j, a) / det
    axis[a] =
        (cofactor(0, a) * joints[0] + cofactor(1, a) * joints[1] + cofactor(2, a) * joints[2]) /
        det;
  }
  pose->tran.x = axis[0];
  pose->tran.y = axis[1];
  pose->tran.z = axis[2];
  pose->a = joints[3];
  pose->b = joints[4];
  pose->c = joints[5];
  return 0;
}

int kinematicsHome(EmcPose* pose, double* joints, KINEMATICS_FORWARD_FLAGS* forward_flags,
                   KINEMATICS_INVERSE_FLAGS* inverse_flags) {
  *forward_flags = 0;
  *inverse_flags = 0;
  return kinematicsForward(joints, pose, forward_flags, inverse_flags);
}

KINEMATICS_TYPE kinematicsType(void) {
  return KINEMATICS_BOTH;
}

int kinematicsSwitchable(void) {
  return 0;
}

int kinematicsSwitch(int) {
  return 0;
}

int rtapi_app_main(void) {
  component = hal_init("pkmtest_matrixkins");
  if (component < 0) return component;
  coefficients = static_cast<Coefficients*>(hal_malloc(sizeof(Coefficients)));
  if (coefficients == nullptr) {
    hal_exit(component);
    return -ENOMEM;
  }
  static const char names[] = "xyz";
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const int result = hal_param_float_newf(HAL_RW, &coefficients->c[r][c], component,
                                              "matrixkins.C_%c%c", names[r], names[c]);
      if (result != 0) {
        hal_exit(component);
        return result;
      }
      coefficients->c[r][c] = r == c ? 1.0 : 0.0;
    }
  }
  hal_ready(component);
  return 0;
}

void rtapi_app_exit(void) {
  hal_exit(component);
}

}  // extern "C"

EXPORT_SYMBOL(kinematicsType);
EXPORT_SYMBOL(kinematicsForward);
EXPORT_SYMBOL(kinematicsInverse);
EXPORT_SYMBOL(kinematicsHome);
EXPORT_SYMBOL(kinematicsSwitchable);
EXPORT_SYMBOL(kinematicsSwitch);
