// lcm-spy itself, counted: starts lcm.spy.Spy (a window: needs a display),
// with or without the receive buffer fix, and after SECONDS prints how many
// messages its channel table counted on CHANNEL (tests of tools/lcm-spy).
//   java evade.tools.SpyRate URL CHANNEL SECONDS FIX(0|1)
// prints "ready" once subscribed, then "<messages counted by lcm-spy>"
package evade.tools;

import java.lang.reflect.Field;
import java.util.Map;

public final class SpyRate {
  private SpyRate() {}

  public static void main(String[] args) throws Exception {
    String url = args[0];
    String channel = args[1];
    double seconds = Double.parseDouble(args[2]);
    boolean fix = args[3].equals("1");
    lcm.spy.Spy spy = new lcm.spy.Spy(url);
    if (fix) {
      Field f = lcm.spy.Spy.class.getDeclaredField("lcm");
      f.setAccessible(true);
      ReceiveBuffer.apply((lcm.lcm.LCM) f.get(spy), ReceiveBuffer.fromUrl(url));
    }
    System.out.println("ready");
    System.out.flush();
    Thread.sleep((long) (seconds * 1000));
    Field m = lcm.spy.Spy.class.getDeclaredField("channelMap");
    m.setAccessible(true);
    Object data = ((Map<?, ?>) m.get(spy)).get(channel);
    long n = data == null ? 0 : ((lcm.spy.ChannelData) data).nreceived;
    System.out.println(n);
    System.out.flush();
    System.exit(0);
  }
}
