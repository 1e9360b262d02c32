// From OpenModelica testsuite/simulation/modelica/events/bug1228.mos (loadString content)
// name: bug1228
// keywords: event, string
// status: correct
package eventTests
  model bug1228
    Real x,y;
    Real a,b;
  equation
    when sample(0,0.2) then
      y = 7 - 2*x+time;
    end when;
    x + y = 5;

    a + b = 5;
    when sample(0,0.2) then
      b = 7 - 2*a+time;
    end when;
  end bug1228;
end eventTests;
