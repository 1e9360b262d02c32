// From OpenModelica testsuite/simulation/modelica/events/EventTests.mos (loadString content)
// name:     EventTest
// keywords: EventHandling, Realations
// status: correct
model testEvents
  parameter Real p = 1;
  Real x(start=-0.25, fixed=true);
  Real y(start=0.25, fixed=true);
  Real a(start=p, fixed=true);
  Boolean v1,v2,v3,v4;
  Boolean w1,w2,w3,w4;
equation
  der(x) = a;
  der(y) = -a;

  v1 = if x >  p then true else false;
  v2 = if x >= p then true else false;
  v3 = if x <  p then true else false;
  v4 = if x <= p then true else false;

  w1 = if x >  y then true else false;
  w2 = if x >= y then true else false;
  w3 = if x <  y then true else false;
  w4 = if x <= y then true else false;

  when sample(1, 1) then
    a = -pre(a);
  end when;
end testEvents;
