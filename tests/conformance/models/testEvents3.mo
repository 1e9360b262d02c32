// From OpenModelica testsuite/simulation/modelica/events/EventTests3.mos (loadString content)
// name:     EventTest3
// keywords: EventHandling, Realations
// status: correct
model testEvents3
  Real x;
equation
  der(x) = 1.0;
  when time > 0.5 then
    reinit(x, 0.0);
  end when;
end testEvents3;
