// From OpenModelica testsuite/simulation/modelica/initialization/startValue.mos (loadString content)
// name: startValue
// keywords: initialization, start-value
// status: correct
//
//  case for start-values
//
within ;
package initializationTests
  model startValue
    Real x(start=-3);
    Real y(start=-3);
  initial equation
    x^2 = 10;
  equation
    der(x) = time;
    y = x;
  end startValue;
end initializationTests;
