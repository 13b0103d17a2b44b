// The version libannex was built as (annex/version.h).
#include "annex/version.h"

namespace annex {

const char* library_version() { return ANNEX_VERSION_STRING; }

}  // namespace annex
