// From OpenModelica testsuite/simulation/modelica/events/whenTest1.mos (loadString content)
// name: whenTest1
// keywords: event, when
// status: correct
//  case for a never active when equation
within ;
package eventTests
  model whenTest1
    Real x;
  equation
    when time > -1.0 then
      x = 1;
    end when;
  end whenTest1;
end eventTests;
