// From OpenModelica testsuite/simulation/modelica/initialization/eventTest2.mos (loadString content)
// name: eventTest2
// keywords: initialization, event-iteration
// status: correct
//  case for events during initialization
// {a = -2, der(a) = 3, d = 2}
within ;
package initializationTests
  model eventTest2
    Real a(start=2);
    Real d;
  initial equation
    a + d = 0;
  equation
    (der(a)-1-d) * (der(a)-3) = 0;
    d = if a > 1 then 1 else 2;
  end eventTest2;
end initializationTests;
