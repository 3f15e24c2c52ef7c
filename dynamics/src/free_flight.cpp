// The straight flight's closed forms (free_flight.hpp), instantiated for the callers that do
// not include that header, in double and in the reference runs' scalar types.
#include "billiards/dynamics/free_flight.hpp"
#include "billiards/dynamics/precision.hpp"

namespace billiards::dynamics {

// (Member by member: a whole-class instantiation would also instantiate the 3-D members.)
template double FreeFlight::exit_time(const State&, const BasicSegmentWall<double>&, const double&) const;
template double FreeFlight::exit_time(const State&, const BasicArcWall<double>&, const double&) const;
template double FreeFlight::exit_time(const State&, const BasicEllipticArcWall<double>&, const double&) const;
template long double BasicFreeFlight<long double>::exit_time(const State&, const BasicSegmentWall<long double>&,
                                                              const long double&) const;
template long double BasicFreeFlight<long double>::exit_time(const State&, const BasicArcWall<long double>&,
                                                              const long double&) const;
template long double BasicFreeFlight<long double>::exit_time(const State&, const BasicEllipticArcWall<long double>&,
                                                              const long double&) const;
template Reference BasicFreeFlight<Reference>::exit_time(const State&, const BasicSegmentWall<Reference>&,
                                                          const Reference&) const;
template Reference BasicFreeFlight<Reference>::exit_time(const State&, const BasicArcWall<Reference>&,
                                                          const Reference&) const;
template Reference BasicFreeFlight<Reference>::exit_time(const State&, const BasicEllipticArcWall<Reference>&,
                                                          const Reference&) const;

}  // namespace billiards::dynamics
