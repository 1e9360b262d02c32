// From OpenModelica testsuite/simulation/modelica/events/MathEventFuncs1.mos (loadString content)
// name:     mathEventsFunction1
// keywords: events, math-functions
// status: correct
// Check for interger valued zerocrossings function
model mathEvents1
  Real u,y1,y2;
equation
  u = 10*sin(10*time);
  y1 = if u > 0 then integer(u) else integer(u)-1;
  y2 = if (u > 0) then integer(floor(u + 0.5)) else integer(ceil(u - 0.5));
end mathEvents1;
