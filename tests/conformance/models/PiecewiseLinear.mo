// From OpenModelica testsuite/simulation/modelica/events/discreteRelations.mos (loadString content)
// name:     discreteRelations
// keywords: events if-expression relations
// status: correct
// Simulate a model with a piecewise linear expression using if-expression.
model PiecewiseLinear
  Real x;
  Real y(start = 1/3);
  Real z(start = 2/3);
equation
  x = sin(time);
  x + (if y > 0 then 2*y else y) - z = 0;
  3*x + y - 1 + z = 0;
annotation(experiment(StartTime = 0, StopTime = 6.28, Tolerance = 1e-06, Interval = 0.001));
end PiecewiseLinear;
