// From OpenModelica testsuite/simulation/modelica/initialization/initial_equation.mos (loadString content)
// name:     initial_equation
// keywords: initialization, start values, initial equation
// status:   correct
//
//  test start values and initial equations
//
within ;
package initializationTests
  model initial_equation1
    Real x;
    Real y;
  initial equation
    x = 5;
    y = 5;
  equation
    der(x) = 2*x*y-3*y;
    der(y) = 5*y-7*x*y;
  end initial_equation1;

  model initial_equation2
    Real x(start=5);
    Real y(start=5);
  equation
    der(x) = 2*x*y-3*y;
    der(y) = 5*y-7*x*y;
  end initial_equation2;

  model initial_equation3
    Real x(start=5);
    Real y(start=5);
  initial equation
    x = 3;
    y = 4;
  equation
    der(x) = 2*x*y-3*y;
    der(y) = 5*y-7*x*y;
  end initial_equation3;
end initializationTests;
