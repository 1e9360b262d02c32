within Lib;
package Sub
  import Lib.Resistor;
  constant Real half = 0.5;
end Sub;
