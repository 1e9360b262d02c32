// From OpenModelica testsuite/simulation/modelica/initialization/startValue2.mos (loadString content)
// name: startValue2
// keywords: initialization, start-value, algebraic variables
// status: correct
model startValue2
  parameter Real a(fixed=false);
  parameter Real b(fixed=false);
  Real w(start=a);
  Real y(start=b);
initial equation
  a=4;
  b=6;
equation
  sin(w*y)+cos(w)*y=time;
  sin(w*y)+sin(y)+w=(a+b)*time;
end startValue2;
