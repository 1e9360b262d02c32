// From OpenModelica testsuite/simulation/modelica/events/divisionByZeroAtEvent.mos (loadString content)
// name: divisionByZeroAtEvent
// keywords: events, division by zero
// status: correct
//
// A division by zero raised while handling an event ends the run: there is no
// step left to retry.
model DivisionByZeroAtEvent
  function eff
    input Real c;
    output Real e;
  algorithm
    e := (1 - exp(-(1 - c)))/(1 - c*exp(-(1 - c)));
  end eff;
  Real c = if time < 0.5 then 2*time else 1;
  Real e = eff(c);
end DivisionByZeroAtEvent;
