// From OpenModelica testsuite/simulation/modelica/initialization/eventTest.mos (loadString content)
// name: eventTest
// keywords: initialization, event-iteration
// status: correct
//  case for events during initialization
// a := 1
// {der(x) = -14/5, der(y) = 1, x = 1/5, y = 1/5}
// a := 2
// {der(x) = -14/25, der(y) = 11/25, x = 1/5, y = 1/5}
within ;
package initializationTests
  model eventTest
    Real x(start=0);
    Real y(start=0);
    Real a;
  initial equation 
    x + y = 2/5;
    x * y = 1/25;
  equation 
    a = if x < 1/25 then 1 else 2;
    a*der(x) + 3*der(y) = x;
    1*der(x) + 4*der(y) = y+1;
  end eventTest;
end initializationTests;
