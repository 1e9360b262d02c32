// From OpenModelica testsuite/simulation/modelica/events/MathEventFuncs2.mos (loadString content)
// name:     mathEventFunctions2
// keywords: events, zerossings, math
// status: correct
// Check for interger valued zerocrossings function
model mathFunctionEvents
  Real u1,u2;
  Real y1;
  Real y2;
  Real y3;
  Integer y4;
  Integer y5;
  Integer y6;
  Integer i1,i2;
equation
  i1 = integer(10*sin(10*time)+30);
  i2 = integer(10*cos(10*time)+15);
  u1 = sin(10*time)-3;
  u2 = cos(10*time)-1.5;
  y1 = div(u1,u2);
  y2 = mod(u1,u2);
  y3 = rem(u1,u2);
  y4 = div(i1,i2);
  y5 = mod(i1,i2);
  y6 = rem(-y4,i2);
end mathFunctionEvents;
