// From OpenModelica testsuite/simulation/modelica/events/TestNoEventsFlags.mos (loadString content)
// name:     testnoEventsFlag
// keywords: EventHandling, Relations
// status: correct
model testnoEventsFlag
  Real x(start=1);
  Boolean b,b1;
equation
  der(x) = 2*x;
  when sample(0,0.2) then
    reinit(x, 1);
  end when;
  b = x > 1.2;
  b1 = der(x) > 2.5;
end testnoEventsFlag;
