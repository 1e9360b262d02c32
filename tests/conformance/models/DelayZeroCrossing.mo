// From OpenModelica testsuite/simulation/modelica/events/DelayZeroCrossing.mos (loadString content)
// name:     DelayZeroCrossing
// keywords: events, delay
// status: correct
//
// A discontinuity in a delay()'s input has to re-trigger an event delayTime later
// (delayZeroCrossing). The state makes the run take the integrator's root-finding
// path, where that crossing is held in pre(zeroCrossing) between steps.
//
package delayTests
  model DelayZeroCrossing
    Real x(start = 0, fixed = true);
    Real u = if time < 0.5 then 0.0 else 1.0;
    Real y = delay(u, 0.1, 0.1);
  equation
    der(x) = 1 - x;
  end DelayZeroCrossing;
end delayTests;
