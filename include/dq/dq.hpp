// Everything in dqkit's header-only core: the algebra and the conversions.
#pragma once

#include "dq/convert/euler.hpp"
#include "dq/convert/matrix.hpp"
#include "dq/convert/screw.hpp"
#include "dq/convert/vrml.hpp"
#include "dq/core/dual.hpp"
#include "dq/core/dual_quaternion.hpp"
#include "dq/core/hyperdual.hpp"
#include "dq/core/hyperdual_quaternion.hpp"
#include "dq/core/matrix.hpp"
#include "dq/core/quaternion.hpp"
#include "dq/core/scalar.hpp"
#include "dq/core/vec3.hpp"
