// From OpenModelica testsuite/simulation/modelica/events/bug2667.mos (loadString content)
// name: bug2667 
// keywords: event, first interval
// status: correct
package eventTests
model bug2667
    Real ramp(start=0, fixed=true);
    Real out;
    Real static_stock(start=1000, fixed=true);
equation
    der(ramp) = 1;
    out = if ramp > 0 then ramp else 0;
    der(static_stock) = 0;
end bug2667;
end eventTests;
