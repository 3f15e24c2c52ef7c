// A reference to a callable that does not own it (as C++26's std::function_ref): a caller's
// lambda passed through a function compiled elsewhere at the cost of one indirect call, with
// neither std::function's copy nor its allocation.  It must not outlive the callable.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>

namespace billiards::dynamics {

template <class Signature>
class FunctionRef;

template <class R, class... Args>
class FunctionRef<R(Args...)> {
 public:
  template <class F>
    requires(!std::is_same_v<std::remove_cvref_t<F>, FunctionRef> && std::is_invocable_r_v<R, F&, Args...>)
  FunctionRef(F&& f)  // (implicit: a lambda is passed where a FunctionRef is asked for)
      : callable_(const_cast<void*>(static_cast<const void*>(std::addressof(f)))),
        call_([](void* callable, Args... args) -> R {
          return (*static_cast<std::remove_reference_t<F>*>(callable))(std::forward<Args>(args)...);
        }) {}
  R operator()(Args... args) const { return call_(callable_, std::forward<Args>(args)...); }

 private:
  void* callable_;
  R (*call_)(void*, Args...);
};

}  // namespace billiards::dynamics
