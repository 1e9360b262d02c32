// From OpenModelica testsuite/simulation/modelica/events/whenTest2.mos (loadString content)
// name: whenTest2
// keywords: event, when
// status: correct
//
// example for when equation without equations, just with statements e.g. reinit, terminate
//
// edit: the when-equation of print(...) calls (no equations, output only) is removed
within ;
package eventTests
  model whenTest2
    Real x(start=1);
  equation
    der(x) = 10*sin(time);
    when x>1.5 then
      reinit(x,1);
    end when;
    when time >= 0.9 then
      terminate("Terminate the model.");
    end when;
    when x > 1.1 then
      assert(time<0.5, "Assert does trigger.", AssertionLevel.warning);
    elsewhen x > 1.2 then
      assert(time<0.55, "Assert does triggered again .", AssertionLevel.warning);
    end when;
  end whenTest2;
end eventTests;
